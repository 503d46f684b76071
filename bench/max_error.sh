#!/bin/sh
# scene-render --max-error E: is the achieved error within E on every scene,
# and how much time does it save against always rendering exactly?
#
#   bench/max_error.sh > bench/RESULTS-max-error.md
#
# Scenes: demo 1 (screen patterns, ortho2), demo 2 through polyfill3 at incr 2
# (flat texel polygons), demo 2 drawn directly (textured), the receding
# checker plane of bench/texture.sh (heavy minification) and a fan of 240
# thin triangles (all edges). For each budget E: the plan scene-render chose,
# the median whole-process time of 5 runs against --aa exact's, and the RMSE
# actually achieved against --reference. Prints one Markdown document.
set -eu
cd "$(dirname "$0")/.."
TARGET=$(cargo metadata --format-version 1 --no-deps | python3 -c 'import json,sys; print(json.load(sys.stdin)["target_directory"])')
cargo build --release --bins >&2
WORK="$TARGET/bench-max-error"
mkdir -p "$WORK"
python3 - "$TARGET/release" "$WORK" "$(pwd)" <<'PY'
import json, os, statistics, subprocess, sys, time

bin_dir, work, root = sys.argv[1:4]
sr = os.path.join(bin_dir, "scene-render")
p3 = os.path.join(bin_dir, "polyfill3")
os.chdir(work)

# The scenes: name -> (stream file, scene-render flags).
def fixture_paths(src, dst):
    text = open(os.path.join(root, src)).read()
    open(dst, "w").write(text.replace('"../../fixtures/', '"%s/fixtures/' % root))

fixture_paths("examples/scenes/demo2.json", "demo2.json")
subprocess.run([p3, "demo2.json", "-o", "demo2-incr2.ndjson"], check=True)
checker = "16 2\n230 230 230\n" + "".join(
    "%04x\n" % (0xAAAA if r % 2 == 0 else 0x5555) for r in range(16)) + "20 20 120\n" + "".join(
    "%04x\n" % (0x5555 if r % 2 == 0 else 0xAAAA) for r in range(16))
open("checker.pat", "w").write(checker)
open("plane.json", "w").write(json.dumps(
    {"vertices": [[-200, 0, -1], [200, 0, -1], [200, 0, -401], [-200, 0, -401]],
     "color": [128, 128, 128], "pattern": {"file": "checker.pat", "incr": 1}}) + "\n")
with open("fan.json", "w") as f:
    import math
    for i in range(240):
        a0, a1 = (i / 240) * 2 * math.pi, ((i + 0.5) / 240) * 2 * math.pi
        c = [250, 40, 40] if i % 2 == 0 else [20, 200, 90]
        f.write(json.dumps({"vertices": [[512, 384], [512 + 370 * math.cos(a0), 384 + 370 * math.sin(a0)],
                                         [512 + 370 * math.cos(a1), 384 + 370 * math.sin(a1)]], "color": c}) + "\n")

D2CAM = ["--perspective", "55,1,0,1000", "--lookat", "0,100,-5,0,0,-900", "--cull", "back",
         "--background-pattern", os.path.join(root, "fixtures/patterns/bkgrnd.pat")]
scenes = [
    ("demo1", [os.path.join(root, "examples/scenes/demo1.json"), "--ortho2", "0,1023,0,767",
               "--background", "255,255,255"]),
    ("demo2-incr2", ["demo2-incr2.ndjson"] + D2CAM),
    ("demo2-direct", ["demo2.json"] + D2CAM),
    ("plane", ["plane.json", "--perspective", "60,1.333,0.5,1000", "--lookat", "0,2,0,0,1.2,-20"]),
    ("fan", ["fan.json", "--ortho2", "0,1024,0,768"]),
]
BUDGETS = ["0.25", "0.5", "1", "2", "4"]
RUNS = 5

def median_time(args):
    ts = []
    for _ in range(RUNS):
        t0 = time.perf_counter()
        subprocess.run([sr] + args, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        ts.append(time.perf_counter() - t0)
    return statistics.median(ts)

def rmse(img, ref):
    out = subprocess.run([sr, "--image", img, "--compare", ref, "--json"], check=True,
                         capture_output=True, text=True).stdout
    return json.loads(out)["compare"]["rmse"]

print("# `scene-render --max-error` benchmark")
print()
load = open("/proc/loadavg").read().split()[:3]
cpu = next((l.split(":", 1)[1].strip() for l in open("/proc/cpuinfo") if l.startswith("model name")), "?")
commit = subprocess.run(["git", "-C", root, "rev-parse", "--short", "HEAD"], capture_output=True,
                        text=True).stdout.strip()
print("Run %s on %s, %d cores (%s), load average %s. Commit %s. 1024x768; whole process "
      "(read, render, write the PNG), median of %d runs. RMSE against `scene-render --reference`, "
      "8-bit sRGB over RGB. 'saved' is 1 - time / time of `--aa exact` (the most accurate method)."
      % (time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime()), os.uname().sysname, os.cpu_count(), cpu,
         " ".join(load), commit, RUNS))
print()
print("| scene | E | plan (flat / textured tiles, pilot tiles) | estimate | achieved RMSE | within E | time s | exact s | saved |")
print("|---|---:|---|---:|---:|---|---:|---:|---:|")
failures = 0
for name, args in scenes:
    args = args + ["--size", "1024x768"]
    subprocess.run([sr] + args + ["--reference", "-o", name + "-ref.png"], check=True,
                   stderr=subprocess.DEVNULL)
    t_exact = median_time(args + ["--aa", "exact", "-o", name + "-exact.png"])
    exact_err = rmse(name + "-exact.png", name + "-ref.png")
    print("| %s | exact | --aa exact | | %.3f | | %.3f | %.3f | 0%% |" % (name, exact_err, t_exact, t_exact))
    for e in BUDGETS:
        out = name + "-" + e + ".png"
        plan = json.loads(subprocess.run([sr] + args + ["--max-error", e, "--json", "-o", out], check=True,
                                         capture_output=True, text=True).stdout)["max_error"]
        t = median_time(args + ["--max-error", e, "-o", out])
        achieved = rmse(out, name + "-ref.png")
        ok = achieved <= float(e)
        failures += not ok
        print("| %s | %s | %s / %s, %d | %.3f | %.3f | %s | %.3f | %.3f | %.0f%% |" % (
            name, e, plan["flat"], plan["textured"], plan["pilot_tiles"], plan["estimate"], achieved,
            "yes" if ok else "**NO**", t, t_exact, 100 * (1 - t / t_exact)))
print()
print("Budgets missed: %d of %d." % (failures, len(scenes) * len(BUDGETS)))
PY
