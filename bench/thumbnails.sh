#!/bin/sh
# Textured scenes drawn small (thumbnails, icons, a far LOD view), where
# many polygons and thousands of texel cells share each pixel:
# `--aa exact` against `--aa ss4` (the cheap supersampled route) and
# against a baseline build, and where the reference is affordable,
# against `--reference`.
#
#   bench/thumbnails.sh [BASELINE_BINDIR] > bench/RESULTS-thumbnails.md
#
# Whole-process time (bench/timing.py: median of 3 after a warm-up; a
# baseline run over 10 s is timed once). 'same' compares the baseline's
# PFM (linear f32) output with this build's, bit for bit, and gives the
# largest difference otherwise. The reference column is the largest
# difference from `--reference` in 8-bit codes, with the reference's own
# uncertain pixel count; it is left out where the reference would take
# minutes (the photographed globes: thousands of texel lines per pixel).
set -eu
cd "$(dirname "$0")/.."
BENCH=thumbnails
. bench/setup.sh
python3 - "$TARGET/release" "$WORK" "${1:-}" "$(pwd)" <<'PY'
import filecmp, json, os, subprocess, sys, time
bin_dir, work, base_dir, repo = sys.argv[1:5]
sys.path.insert(0, os.path.join(repo, "bench"))
from timing import measure, run_once

sr = os.path.join(bin_dir, "scene-render")
base = os.path.join(os.path.abspath(base_dir), "scene-render") if base_dir else None
fix = os.path.join(repo, "fixtures")
demo2 = os.path.join(repo, "examples/scenes/demo2.json")
DEMO2 = ["--perspective", "55,1,0,1000", "--lookat", "0,100,-5,0,0,-900", demo2]
GLOBES = ["--ortho", "-80,80,-60,60,0,100"]
HOUSE = ["--perspective", "40,auto,1,500", "--lookat", "30,25,60,0,10,0", f"{fix}/scenes/house.json"]
ROWS = [  # name, arguments, size, whether the reference is affordable
    ("demo 2", DEMO2, "1024x768", False),
    ("demo 2", DEMO2, "64x48", True),
    ("demo 2", DEMO2, "8x8", True),
    ("two spheres", GLOBES + [f"{fix}/scenes/two-spheres.json"], "25x19", True),
    ("photographed globes", GLOBES + [f"{fix}/scenes/earth-photo.json"], "800x600", False),
    ("photographed globes", GLOBES + [f"{fix}/scenes/earth-photo.json"], "100x75", False),
    ("lit globes", GLOBES + [f"{fix}/scenes/earth-lit.json"], "200x150", False),
    ("house", HOUSE, "480x360", False),
    ("house", HOUSE, "60x45", False),
]
os.chdir(work)


def time_of(binary, args, out, slow_once=False):
    cmd = [binary] + args + ["-o", out]
    first, _ = run_once(cmd)
    if slow_once and first > 10:
        return first
    return measure(cmd, runs=3, warmup=0)[0]


def largest(img, ref):
    out = subprocess.run([sr, "--image", img, "--compare", ref, "--json"], check=True,
                         capture_output=True, text=True).stdout
    return json.loads(out)["compare"]


load = ", ".join("%.2f" % l for l in os.getloadavg())
commit = subprocess.run(["git", "-C", repo, "rev-parse", "--short", "HEAD"], capture_output=True,
                        text=True).stdout.strip()
print("# Textured scenes drawn small")
print()
print(f"Run {time.strftime('%Y-%m-%d %H:%M', time.gmtime())} UTC at commit {commit}, {os.cpu_count()} cores, "
      f"load average {load}. Whole process, seconds (median of 3; a baseline run over 10 s timed once).")
print()
head = "| scene | size | exact s | ss4 s | exact / ss4 | "
if base:
    head += "baseline exact s | baseline / exact | same as baseline | "
head += "vs reference (max codes, uncertain pixels) |"
print(head)
print("|" + "---|" * (head.count("|") - 1))
for name, args, size, with_ref in ROWS:
    a = args + ["--size", size]
    exact = time_of(sr, a, "exact.pfm")
    ss4 = time_of(sr, a + ["--aa", "ss4"], "ss4.png")
    row = f"| {name} | {size} | {exact:.3f} | {ss4:.3f} | {exact / ss4:.2f} | "
    if base:
        b = time_of(base, a, "base.pfm", slow_once=True)
        if filecmp.cmp("base.pfm", "exact.pfm", shallow=False):
            same = "yes"
        else:
            c = largest("exact.pfm", "base.pfm")
            same = f"no: largest {c['linear']['largest_error']:.1e} linear"
        row += f"{b:.3f} | {b / exact:.1f} | {same} | "
    if with_ref:
        rep = json.loads(subprocess.run([sr] + a + ["--reference", "--json", "-o", "ref.png"], check=True,
                                        capture_output=True, text=True).stdout)["reference"]
        subprocess.run([sr] + a + ["-o", "exact.png"], check=True, capture_output=True)
        c = largest("exact.png", "ref.png")
        row += f"{c['largest_error']}, {rep['uncertain_pixels']} |"
    else:
        row += "— |"
    print(row)
PY
