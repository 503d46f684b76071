#!/bin/sh
# Does a textured scene use both cores? (issue 20, item 4)
#
#   bench/threads.sh > bench/RESULTS-threads.md
#
# Demo 2 drawn directly (its pyramid and plain textured by scene-render, the
# IRIS background pattern behind), with and without the background pattern,
# at 2048x2048 and 4096x4096: the render phase of --timings (projection to
# encoded pixels), median of 5 runs after a warm-up, with --threads 1 and
# --threads 2 taking turns (bench/timing.py), the
# ratio, and whether the two images are byte-identical. Goal: 2 threads at
# most 0.6x one thread at 2048x2048. Prints one Markdown document.
set -eu
cd "$(dirname "$0")/.."
BENCH=threads
. bench/setup.sh
python3 - "$TARGET/release" "$WORK" "$(pwd)" <<'PY'
import filecmp, os, sys, time

bin_dir, work, root = sys.argv[1:4]
sys.path.insert(0, os.path.join(root, "bench"))
from timing import measure_in_turns
sr = os.path.join(bin_dir, "scene-render")
os.chdir(work)
text = open(os.path.join(root, "examples/scenes/demo2.json")).read()
open("demo2.json", "w").write(text.replace('"../../fixtures/', '"%s/fixtures/' % root))
VIEW = ["--perspective", "55,1,0,1000", "--lookat", "0,100,-5,0,0,-900", "--cull", "back"]
BG = ["--background-pattern", os.path.join(root, "fixtures/patterns/bkgrnd.pat")]


def render_times(size, extra):
    """The median render phase with one thread and with two, of 5 rounds
    after a warm-up, the two taking turns (bench/timing.py); the images are
    left in one.ppm and two.ppm."""
    cmds = [[sr, "--threads", threads, "--size", size, "--timings"] + VIEW + extra + ["demo2.json", "-o", out]
            for threads, out in [("1", "one.ppm"), ("2", "two.ppm")]]
    return [ph["render"] for _, ph in measure_in_turns(cmds, 5)]


load = ", ".join("%.2f" % l for l in os.getloadavg())
print("# Threads on a textured scene (issue 20, item 4)")
print()
print(f"Run {time.strftime('%Y-%m-%d %H:%M', time.gmtime())} UTC, {os.cpu_count()} cores, load average {load}. "
      "Demo 2 drawn directly, `--aa exact`; render phase of `--timings`, median of 5 runs after a warm-up, "
      "one and two threads taking turns (bench/timing.py).")
print()
print("| size | background | 1 thread s | 2 threads s | 2 / 1 | identical |")
print("|---|---|---:|---:|---:|---|")
for size in ["2048x2048", "4096x4096"]:
    for name, extra in [("colour", []), ("bkgrnd.pat", BG)]:
        one, two = render_times(size, extra)
        same = "yes" if filecmp.cmp("one.ppm", "two.ppm", shallow=False) else "**no**"
        print(f"| {size} | {name} | {one:.3f} | {two:.3f} | {two / one:.2f} | {same} |")
PY
