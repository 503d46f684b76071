#!/bin/sh
# A one-texel checker ground to its horizon (issue 15): the default --aa
# exact against --reference, and against a baseline build, at 0 degrees,
# 45 degrees and an irrational angle.
#
#   bench/horizon.sh [BASELINE_BINDIR] > bench/RESULTS-horizon.md
#
# Each scene: 640x360, eye 3 units over a 40,000-unit ground, horizon in
# the middle of the frame. Whole-process time (read, render, write the PNG),
# median of 5 runs after a warm-up (bench/timing.py), for this build's scene-render and, when BASELINE_BINDIR
# is given, for that directory's (say, a build of the commit before a
# change) side by side as a ratio; the fragments --aa exact reports as
# estimated (its warning); the reference's own uncertainty; and each image
# against the reference. Prints one Markdown document.
set -eu
cd "$(dirname "$0")/.."
BENCH=horizon
. bench/setup.sh
python3 - "$TARGET/release" "$WORK" "${1:-}" <<'PY'
import json, os, re, subprocess, sys, time

bin_dir, work, base_dir = sys.argv[1:4]
sys.path.insert(0, os.path.join(os.getcwd(), "bench"))
from timing import measure, run_logged
sr = os.path.join(bin_dir, "scene-render")
base = os.path.join(os.path.abspath(base_dir), "scene-render") if base_dir else None
os.chdir(work)

checker = "16 2\n230 230 230\n" + "".join(
    "%04x\n" % (0xAAAA if r % 2 == 0 else 0x5555) for r in range(16)) + "20 20 120\n" + "".join(
    "%04x\n" % (0x5555 if r % 2 == 0 else 0xAAAA) for r in range(16))
open("checker.pat", "w").write(checker)
VIEW = ["--size", "640x360", "--perspective", "60,auto,0.5,100000",
        "--lookat", "0.3,3,0.7,0.3,3,-100.7", "--background", "90,140,200"]
ANGLES = [("0", 0.0), ("45", 45.0), ("100/e", 100 / 2.718281828459045)]


def median_time(cmd):
    """Whole process, median of 5 runs after a warm-up (bench/timing.py)."""
    return measure(cmd, runs=5)[0]


def compare(img, ref):
    out = subprocess.run([sr, "--image", img, "--compare", ref, "--json"], check=True,
                         capture_output=True, text=True).stdout
    return json.loads(out)["compare"]


print("# Horizon benchmark: a one-texel checker ground to its horizon (issue 15)")
print()
load = ", ".join("%.2f" % l for l in os.getloadavg())
commit = subprocess.run(["git", "-C", os.path.dirname(os.path.abspath(sys.argv[0])) or ".", "rev-parse", "--short", "HEAD"],
                        capture_output=True, text=True).stdout.strip()
print(f"Run {time.strftime('%Y-%m-%d %H:%M', time.gmtime())} UTC, {os.cpu_count()} cores, load average {load}. "
      f"640x360, eye 3 units up, whole process, median of 5 runs after a warm-up (bench/timing.py). "
      f"Errors in 8-bit sRGB codes against `--reference`; 'estimated' is the fragment count of --aa exact's warning.")
print()
cols = "| angle | exact s | " + ("baseline s | exact / baseline | " if base else "") + \
    "estimated | reference s | reference uncertain pixels | exact RMSE | exact max | " + \
    ("baseline RMSE | baseline max |" if base else "")
print(cols)
print("|" + "---|" * (cols.count("|") - 1))
for name, deg in ANGLES:
    scene = f"ground-{deg:.6f}.json"
    open(scene, "w").write(json.dumps(
        {"vertices": [[-20000, 0, 20000], [20000, 0, 20000], [20000, 0, -20000], [-20000, 0, -20000]],
         "pattern": {"file": "checker.pat", "incr": 1, "rotate": deg}}) + "\n")
    exact = median_time([sr] + VIEW + [scene, "-o", "exact.png"])
    warn = subprocess.run([sr] + VIEW + [scene, "-o", "exact.png"], check=True, capture_output=True, text=True).stderr
    m = re.search(r"(\d+) pixel fragment\(s\) too fine to integrate exactly", warn)
    estimated = m.group(1) if m else "0"
    # One run: the reference takes seconds (bench/timing.py).
    r = run_logged([sr] + VIEW + [scene, "--reference", "--json", "-o", "ref.png"], keep_stdout=True)
    ref, ref_s = json.loads(r.stdout)["reference"], r.wall
    c = compare("exact.png", "ref.png")
    row = f"| {name} | {exact:.3f} | "
    if base:
        b = median_time([base] + VIEW + [scene, "-o", "base.png"])
        row += f"{b:.3f} | {exact / b:.2f} | "
    row += f"{estimated} | {ref_s:.2f} | {ref['uncertain_pixels']} | {c['rmse']:.4f} | {c['largest_error']} |"
    if base:
        cb = compare("base.png", "ref.png")
        row += f" {cb['rmse']:.4f} | {cb['largest_error']} |"
    print(row)
print()
print("The reference is uncertain only where a pixel meets more than 1,024 texel lines of one direction or the "
      "plane's horizon (`raster::reference::MAX_TEXEL_LINES`); its estimate there is the texture's whole contrast. "
      "Where it is certain, `scene::horizon_tests` checks that the default gives its very code.")
PY
