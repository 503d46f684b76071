#!/usr/bin/env python3
"""Crowded pixels under `--aa exact` (hostile inputs for the exact sweep,
which checks each fragment against those that showed in its pixel before
it), time against N, this build and a baseline's in one run, as a table.

    python3 bench/crowded_pixels.py BINDIR [BASELINE_BINDIR] > bench/RESULTS-crowded-pixels.md

- fan: N triangles, each its own record and colour, from the hub (128.3,
  128.7) to a circle of radius 100 in a 256x256 frame, the rim's depths
  0.5 sin(3a), so that neighbours are tilted differently (the hub index of
  src/raster/crowd.rs);
- strip: N thin triangles side by side, N/2 quads 0.5/(N/2) pixel wide and
  19.6 long, turned 0.6 rad, sharing edges and no one vertex, all crossing
  the same few pixels of an 8x24 frame (the axis index);
- star-under, star-over: one concave polygon, a star of N vertices
  alternating between radii 7 and 5 round (8, 8) (the stress tests' star),
  and one triangle over most of a 16x16 frame, in front of the star (z 0.5:
  the star under it) or behind it (z -0.5: the star over it): a pixel's map
  and uncovered part under thousands of the star's pieces
  (`PixelStates::overtake`, `cut_out`).

Times: the render phase (`--timings`) of bench/timing.py's
`measure_in_turns` (the builds taking turns, median of 3 after a warm-up);
the images must be the same bytes. A baseline run slower than TIMEOUT
seconds (default 60) once, unmeasured, is shown as more than that, and no
larger N of that set is run on it.
"""
import math
import os
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from timing import measure_in_turns  # noqa: E402

SETS = {
    "fan": ((5_000, 10_000, 20_000, 40_000), "256x256"),
    "strip": ((1_000, 2_000, 4_000, 8_000), "8x24"),
    "star-under": ((10_000, 20_000, 30_000, 50_000), "16x16"),
    "star-over": ((10_000, 20_000, 30_000, 50_000), "16x16"),
}


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


def strip(n, path):
    quads, turn = n // 2, 0.6
    w = 0.5 / quads
    cos, sin = math.cos(turn), math.sin(turn)

    def at(x, y, z):
        x, y = x - 4, y - 12
        return "[%r,%r,%r]" % (4 + cos * x - sin * y, 12 + sin * x + cos * y, z)

    with open(path, "w") as out:
        for i in range(quads):
            xa, xb = 3.7 + i * w, 3.7 + (i + 1) * w
            b0, b1, t0, t1 = at(xa, 2.2, 0.0), at(xb, 2.2, 0.0), at(xa, 21.8, 0.3), at(xb, 21.8, 0.3)
            c = "[%d,%d,%d]" % ((i * 37) % 256, (i * 91) % 256, (i * 13) % 256)
            out.write('{"vertices":[%s,%s,%s],"color":%s}\n' % (b0, b1, t1, c))
            out.write('{"vertices":[%s,%s,%s],"color":%s}\n' % (b0, t1, t0, c))


def star(n, path, depth):
    with open(path, "w") as out:
        pts = []
        for i in range(n):
            a, r = 2 * math.pi * i / n, (7.0, 5.0)[i % 2]
            pts.append("[%r,%r]" % (8 + r * math.cos(a), 8 + r * math.sin(a)))
        out.write('{"vertices":[%s],"color":[255,255,255]}\n' % ",".join(pts))
        out.write('{"vertices":[[0,0,%r],[16,2,%r],[3,16,%r]],"color":[255,0,0]}\n' % ((depth,) * 3))


def main():
    builds = [("this build", sys.argv[1])] + ([("baseline", sys.argv[2])] if len(sys.argv) > 2 else [])
    timeout = float(os.environ.get("TIMEOUT", "60"))
    work = tempfile.mkdtemp()
    cols = " | ".join(f"{b} render (s)" for b, _ in builds)
    ratio = " | baseline / this build" if len(builds) > 1 else ""
    print(f"| set | N | {cols}{ratio} |")
    print("|---|---:|" + "---:|" * (len(builds) + (len(builds) > 1)))
    fits = []
    for name, (sizes, size) in SETS.items():
        gave_up = set()
        rows = []
        for n in sizes:
            scene = os.path.join(work, f"{name}-{n}.ndjson")
            {
                "fan": fan,
                "strip": strip,
                "star-under": lambda n, path: star(n, path, 0.5),
                "star-over": lambda n, path: star(n, path, -0.5),
            }[name](n, scene)
            cmds, names = [], []
            for b, d in builds:
                if b in gave_up:
                    continue
                out = os.path.join(work, f"{b.replace(' ', '-')}-{name}-{n}.png")
                cmd = [os.path.join(d, "scene-render"), "--size", size, "--timings", scene, "-o", out]
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
                raise SystemExit(f"crowded_pixels.py: {name}, N = {n}: the images differ")
            render = {b: m[1]["render"] for b, m in measured.items()}
            cells = [f"{render[b]:.3f}" if b in render else f"> {timeout:.0f}" for b, _ in builds]
            if len(builds) > 1:
                both = all(b in render for b, _ in builds)
                cells.append(f"{render['baseline'] / render['this build']:.1f}" if both else "-")
            rows.append((n, render))
            print(f"| {name} | {n} | " + " | ".join(cells) + " |")
        (n0, r0), (n1, r1) = rows[0], rows[-1]
        for b, _ in builds:
            if b in r0 and b in r1:
                exp = math.log(r1[b] / r0[b]) / math.log(n1 / n0)
                fits.append(f"- {name}, {b}: render time ~ N^{exp:.2f} from N = {n0} to {n1}.")
    print()
    print("\n".join(fits))


if __name__ == "__main__":
    main()
