#!/bin/sh
# Does a textured scene use both cores? (issue 20, item 4)
#
#   bench/threads.sh > bench/RESULTS-threads.md
#
# Demo 2 drawn directly (its pyramid and plain textured by scene-render, the
# IRIS background pattern behind), with and without the background pattern,
# at 2048x2048 and 4096x4096: the render phase of --timings (projection to
# encoded pixels), median of 5 runs, with --threads 1 and --threads 2, the
# ratio, and whether the two images are byte-identical. Goal: 2 threads at
# most 0.6x one thread at 2048x2048. Prints one Markdown document.
set -eu
cd "$(dirname "$0")/.."
BENCH=threads
. bench/setup.sh
python3 - "$TARGET/release" "$WORK" "$(pwd)" <<'PY'
import filecmp, os, re, statistics, subprocess, sys, time

bin_dir, work, root = sys.argv[1:4]
sr = os.path.join(bin_dir, "scene-render")
os.chdir(work)
text = open(os.path.join(root, "examples/scenes/demo2.json")).read()
open("demo2.json", "w").write(text.replace('"../../fixtures/', '"%s/fixtures/' % root))
VIEW = ["--perspective", "55,1,0,1000", "--lookat", "0,100,-5,0,0,-900", "--cull", "back"]
BG = ["--background-pattern", os.path.join(root, "fixtures/patterns/bkgrnd.pat")]


def render_time(threads, size, extra, out):
    times = []
    for _ in range(5):
        err = subprocess.run([sr, "--threads", threads, "--size", size, "--timings"] + VIEW + extra +
                             ["demo2.json", "-o", out], check=True, capture_output=True, text=True).stderr
        times.append(float(re.search(r"render ([0-9.]+) s", err).group(1)))
    return statistics.median(times)


load = ", ".join("%.2f" % l for l in os.getloadavg())
print("# Threads on a textured scene (issue 20, item 4)")
print()
print(f"Run {time.strftime('%Y-%m-%d %H:%M', time.gmtime())} UTC, {os.cpu_count()} cores, load average {load}. "
      "Demo 2 drawn directly, `--aa exact`; render phase of `--timings`, median of 5 runs.")
print()
print("| size | background | 1 thread s | 2 threads s | 2 / 1 | identical |")
print("|---|---|---:|---:|---:|---|")
for size in ["2048x2048", "4096x4096"]:
    for name, extra in [("colour", []), ("bkgrnd.pat", BG)]:
        one = render_time("1", size, extra, "one.ppm")
        two = render_time("2", size, extra, "two.ppm")
        same = "yes" if filecmp.cmp("one.ppm", "two.ppm", shallow=False) else "**no**"
        print(f"| {size} | {name} | {one:.3f} | {two:.3f} | {two / one:.2f} | {same} |")
PY
