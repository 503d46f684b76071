#!/usr/bin/env python3
"""Seeded random flat triangles for the exact anti-aliasing scaling benchmark
(bench/aa_scaling.sh; issue "Performance at scale", item 1).

    python3 bench/random_triangles.py N auto|S [SEED] > scene.ndjson

1024x768 frame under scene-render's default view (pixel coordinates), N
triangles with centres uniform in the frame and each vertex within +-s of its
centre in x and y. `auto` picks s = sqrt(4*W*H / (0.3*N)), so that about four
triangles overlap each pixel (a triangle with vertices uniform in a 2s square
has mean area about 0.076*(2s)^2 = 0.3*s^2); a number fixes s in pixels.
Depths uniform in (-1, 1), colours uniform. Standard library only, so the
scene is the same wherever it is generated.
"""
import math
import random
import sys

W, H = 1024, 768


def main():
    n = int(sys.argv[1])
    s = math.sqrt(4 * W * H / (0.3 * n)) if sys.argv[2] == "auto" else float(sys.argv[2])
    rng = random.Random(int(sys.argv[3]) if len(sys.argv) > 3 else 1)
    out = sys.stdout
    for _ in range(n):
        cx, cy = rng.uniform(0, W), rng.uniform(0, H)
        v = ",".join(
            "[%.3f,%.3f,%.4f]" % (cx + rng.uniform(-s, s), cy + rng.uniform(-s, s), rng.uniform(-1, 1))
            for _ in range(3)
        )
        c = rng.randrange(256), rng.randrange(256), rng.randrange(256)
        out.write('{"vertices":[%s],"color":[%d,%d,%d]}\n' % (v, *c))


if __name__ == "__main__":
    main()
