#!/usr/bin/env python3
"""Fans of triangles round one vertex under `--aa exact` (a hostile input
for the exact sweep: every triangle reaches the pixels round the hub), time
against N, this build and a baseline's in one run, printed as a table.

    python3 bench/fan.py BINDIR [BASELINE_BINDIR] > bench/RESULTS-fan.md

Each scene: N triangles, each its own record and colour, from the hub
(128.3, 128.7) to a circle of radius 100 in a 256x256 frame, the rim's
depths 0.5 sin(3a) so that neighbours are tilted differently. Times: the
render phase (`--timings`) of bench/timing.py's `measure_in_turns` (the
builds taking turns, median of 3 after a warm-up); the images must be the
same bytes. A baseline run slower than TIMEOUT seconds (default 60) once,
unmeasured, is shown as more than that, and no larger N is run on it.
"""
import math
import os
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from timing import measure_in_turns  # noqa: E402

SIZES = (5_000, 10_000, 20_000, 40_000)


def fan(n, path):
    cx, cy, r = 128.3, 128.7, 100.0
    with open(path, "w") as out:
        for i in range(n):
            a0, a1 = 2 * math.pi * i / n, 2 * math.pi * (i + 1) / n
            out.write('{"vertices":[[%r,%r,0.0],[%r,%r,%r],[%r,%r,%r]],"color":[%d,%d,%d]}\n' % (
                cx, cy,
                cx + r * math.cos(a0), cy + r * math.sin(a0), 0.5 * math.sin(3 * a0),
                cx + r * math.cos(a1), cy + r * math.sin(a1), 0.5 * math.sin(3 * a1),
                (i * 37) % 256, (i * 91) % 256, (i * 13) % 256))


def main():
    builds = [("this build", sys.argv[1])] + ([("baseline", sys.argv[2])] if len(sys.argv) > 2 else [])
    timeout = float(os.environ.get("TIMEOUT", "60"))
    work = tempfile.mkdtemp()
    cols = " | ".join(f"{b} render (s)" for b, _ in builds)
    ratio = " | baseline / this build" if len(builds) > 1 else ""
    print(f"| N | {cols}{ratio} |")
    print("|---:|" + "---:|" * (len(builds) + (len(builds) > 1)))
    gave_up = set()
    rows = []
    for n in SIZES:
        scene = os.path.join(work, f"fan-{n}.ndjson")
        fan(n, scene)
        cmds, names = [], []
        for b, d in builds:
            out = os.path.join(work, f"{b.replace(' ', '-')}-{n}.png")
            cmd = [os.path.join(d, "scene-render"), "--size", "256x256", "--timings", scene, "-o", out]
            if b in gave_up:
                continue
            try:
                subprocess.run(cmd, capture_output=True, check=True, timeout=timeout)
            except subprocess.TimeoutExpired:
                gave_up.add(b)
                continue
            cmds.append(cmd)
            names.append((b, out))
        measured = dict(zip((b for b, _ in names), measure_in_turns(cmds, runs=3)))
        images = {open(out, "rb").read() for _, out in names}
        if len(images) > 1:
            raise SystemExit(f"fan.py: N = {n}: the images differ")
        cells = [f"{measured[b][1]['render']:.3f}" if b in measured else f"> {timeout:.0f}" for b, _ in builds]
        if len(builds) > 1:
            t = [measured[b][1]["render"] if b in measured else None for b, _ in builds]
            cells.append(f"{t[1] / t[0]:.1f}" if None not in t else "-")
        rows.append((n, measured))
        print(f"| {n} | " + " | ".join(cells) + " |")
    print()
    (n0, m0), (n1, m1) = rows[0], rows[-1]
    for b, _ in builds:
        if b in m0 and b in m1:
            exp = math.log(m1[b][1]["render"] / m0[b][1]["render"]) / math.log(n1 / n0)
            print(f"- {b}: render time ~ N^{exp:.2f} from N = {n0} to {n1}.")


if __name__ == "__main__":
    main()
