#!/usr/bin/env python3
"""Seeded layered meshes for the exact anti-aliasing scaling benchmark
(bench/aa_scaling.sh; issue "Performance at scale", item 1): the mesh case
beside bench/random_triangles.py's triangle soup.

    python3 bench/layered_mesh.py N [SEED] > scene.ndjson

1024x768 frame under scene-render's default view (pixel coordinates), four
sheets, each a grid of about N/4 triangles over the whole frame (two a
cell), so about four layers a pixel, as in the soup. Inside a sheet
triangles share their edges exactly (the same vertex text), as in an
imported model; each grid vertex is moved by up to 0.3 of a cell in x and y
so that edges do not follow the pixel grid. Depth: sheet k's base is
-0.6 + 0.4 k, plus a wave of amplitude 0.3, so neighbouring sheets cross
along curves where their waves meet, as interpenetrating parts of a model
do. Colours uniform, one a triangle. Standard library only, so the scene is
the same wherever it is generated.
"""
import math
import random
import sys

W, H = 1024, 768
SHEETS = 4


def main():
    n = int(sys.argv[1])
    rng = random.Random(int(sys.argv[2]) if len(sys.argv) > 2 else 1)
    # Cells of aspect W:H, two triangles each, N/SHEETS triangles a sheet.
    cells = max(1, n // (2 * SHEETS))
    cols = max(1, round(math.sqrt(cells * W / H)))
    rows = max(1, cells // cols)
    dx, dy = W / cols, H / rows
    out = sys.stdout
    for k in range(SHEETS):
        base = -0.6 + 0.4 * k
        fx, fy, phase = rng.uniform(2, 5), rng.uniform(2, 5), rng.uniform(0, 2 * math.pi)
        verts = []
        for j in range(rows + 1):
            row = []
            for i in range(cols + 1):
                # The frame's border stays straight, so the sheet covers it.
                jx = 0 if i in (0, cols) else rng.uniform(-0.3, 0.3) * dx
                jy = 0 if j in (0, rows) else rng.uniform(-0.3, 0.3) * dy
                x, y = i * dx + jx, j * dy + jy
                z = base + 0.3 * math.sin(fx * x / W * 2 * math.pi + phase) * math.cos(fy * y / H * 2 * math.pi)
                row.append("[%.3f,%.3f,%.4f]" % (x, y, z))
            verts.append(row)
        for j in range(rows):
            for i in range(cols):
                a, b, c, d = verts[j][i], verts[j][i + 1], verts[j + 1][i + 1], verts[j + 1][i]
                for tri in ((a, b, c), (a, c, d)):
                    col = rng.randrange(256), rng.randrange(256), rng.randrange(256)
                    out.write('{"vertices":[%s],"color":[%d,%d,%d]}\n' % (",".join(tri), *col))


if __name__ == "__main__":
    main()
