#!/usr/bin/env python3
"""polyfill3 on polygons of many vertices: time against the vertex count at a
fixed number of cells (README, "Limits").

    polyfill3_vertices.py BINDIR WORK [--baseline BINDIR]

Two shapes, each one concave polygon in brick.pat at incr 1, its first edge
along the bottom so that the pattern's rows run across it:

- `sliver`: 1 texel wide and 100,000 tall, V vertices up each side (V =
  500, 5,000, 50,000), wiggling by a tenth of a texel: 100,000 rows, each
  met by the few edges near it.
- `comb`: T teeth (T = 1,000, 4,000, 16,000) 1 texel wide and 2 apart on a
  base, all within one row: one strip of 5T vertices, every column a
  boundary column.

Whole process, `-o` a file, median of RUNS (3) after a warm-up
(bench/timing.py), peak resident memory of one more run. With --baseline,
another build's polyfill3 takes turns with this one and the two outputs are
compared byte for byte.
"""
import math
import os
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from timing import measure_in_turns, run_once  # noqa: E402

ROWS = 100_000
PATTERN = os.path.abspath(
    os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "fixtures", "patterns", "brick.pat")
)


def sliver(v):
    """V vertices a side, counter-clockwise from the bottom left."""
    left = [(0.2 + 0.1 * math.sin(i * 0.7), ROWS * i / (v - 1)) for i in range(v)]
    right = [(0.8 + 0.1 * math.cos(i * 0.9), ROWS * i / (v - 1)) for i in range(v)]
    return [left[0]] + (right + left[::-1])[:-1]


def comb(t):
    """T teeth up from a base 0.3 tall, all below y = 1."""
    ring = [(0.0, 0.0), (2.0 * t, 0.0)]
    for i in reversed(range(t)):
        x0 = 2.0 * i + 0.25
        ring += [(x0 + 1.0, 0.3), (x0 + 1.0, 0.9), (x0 + 0.5, 0.95), (x0, 0.9), (x0, 0.3)]
    return ring + [(0.0, 0.3)]


def record(ring):
    verts = ",".join("[%r,%r,0]" % p for p in ring)
    return '{"vertices":[%s],"color":[200,100,50],"pattern":{"file":"%s","incr":1}}\n' % (verts, PATTERN)


def fit(xs, ys):
    """The exponent b of y = a * x^b, least squares in log-log."""
    lx, ly = [math.log(x) for x in xs], [math.log(y) for y in ys]
    mx, my = sum(lx) / len(lx), sum(ly) / len(ly)
    return sum((a - mx) * (b - my) for a, b in zip(lx, ly)) / sum((a - mx) ** 2 for a in lx)


SHAPES = [("sliver", sliver, [500, 5000, 50000]), ("comb", comb, [1000, 4000, 16000])]


def main(argv):
    bindir, work, rest = argv[0], argv[1], argv[2:]
    baseline = rest[1] if rest[:1] == ["--baseline"] else None
    runs = int(os.environ.get("RUNS", "3"))
    head = "| shape | size | vertices | cells | polyfill3 (s) | peak (MB) | ns a cell |"
    rule = "|---|---:|---:|---:|---:|---:|---:|"
    if baseline:
        head += " baseline (s) | baseline/polyfill3 | same bytes |"
        rule += "---:|---:|---|"
    print(head)
    print(rule)
    fits = []
    for name, make, sizes in SHAPES:
        verts, times = [], []
        for size in sizes:
            ring = make(size)
            scene = os.path.join(work, f"{name}-{size}.json")
            with open(scene, "w") as f:
                f.write(record(ring))
            out = os.path.join(work, f"{name}-{size}.ndjson")
            cmds = [[os.path.join(bindir, "polyfill3"), scene, "-o", out]]
            if baseline:
                cmds.append([os.path.join(baseline, "polyfill3"), scene, "-o", out + ".baseline"])
            results = measure_in_turns(cmds, runs=runs, warmup=1)
            wall = results[0][0]
            peak = run_once(cmds[0], gnu_time=True)[1]
            with open(out) as f:
                cells = sum(1 for _ in f)
            row = (
                f"| {name} | {size:,} | {len(ring):,} | {cells:,} | {wall:.3f} | {peak / 1024:.1f} |"
                f" {wall / cells * 1e9:.0f} |"
            )
            if baseline:
                base = results[1][0]
                same = subprocess.run(["cmp", "-s", out, out + ".baseline"]).returncode == 0
                row += f" {base:.3f} | {base / wall:.1f} | {'yes' if same else 'NO'} |"
            print(row, flush=True)
            verts.append(len(ring))
            times.append(wall)
        fits.append(f"- {name}: time ~ V^{fit(verts, times):.2f} over V = {', '.join(f'{v:,}' for v in verts)}.")
    print()
    print("\n".join(fits))


if __name__ == "__main__":
    main(sys.argv[1:])
