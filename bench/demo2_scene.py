#!/usr/bin/env python3
"""The thesis's demo 2 (App. C, Fig. 4.10) as a flat-coloured polygon stream.

A stand-in for `polyfill3` used by bench/scene_render.sh when polyfill3 is not
built: each polygon is partitioned into its texture point polygons exactly as
docs/stream-format.md object mode says (origin at vertex 0, +x along vertex0->vertex1, +y 90
degrees counter-clockwise from the front, texel squares of side `incr` from the
plane bounding box's lower-left, shifted by horz/vert texels), each texel square
clipped to the polygon; transparent texels are left out.

usage: demo2_scene.py PATTERN_DIR PYRAMID_INCR > scene.ndjson
"""
import json
import math
import sys


def read_pat(path):
    words = open(path).read().split()
    size, ncolors = int(words[0]), int(words[1])
    pos = 2
    per_row = size // 16
    tex = [[None] * size for _ in range(size)]
    for _ in range(ncolors):
        rgb = [int(w) for w in words[pos:pos + 3]]
        pos += 3
        for row in range(size):
            for w in range(per_row):
                word = int(words[pos], 16)
                pos += 1
                for b in range(16):
                    if word & (0x8000 >> b):
                        tex[row][w * 16 + b] = rgb
    return size, tex


def sub(a, b):
    return [a[i] - b[i] for i in range(3)]


def cross(a, b):
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


def norm(a):
    n = math.sqrt(sum(x * x for x in a))
    return [x / n for x in a]


def clip(poly, k, value, keep_above):
    out = []
    n = len(poly)
    for i in range(n):
        a, b = poly[i], poly[(i + 1) % n]
        da = a[k] - value if keep_above else value - a[k]
        db = b[k] - value if keep_above else value - b[k]
        if da >= 0:
            out.append(a)
            if db < 0 and da > 0:
                t = da / (da - db)
                out.append([a[0] + (b[0] - a[0]) * t, a[1] + (b[1] - a[1]) * t])
        elif db > 0:
            t = db / (db - da)
            out.append([b[0] + (a[0] - b[0]) * t, b[1] + (a[1] - b[1]) * t])
    return out


def partition(verts, pat, incr, horz, vert, out):
    size, tex = pat
    o = verts[0]
    ex = norm(sub(verts[1], o))
    nrm = norm(cross(sub(verts[1], o), sub(verts[2], o)))
    ey = cross(nrm, ex)
    plane = [[sum(sub(v, o)[i] * ex[i] for i in range(3)), sum(sub(v, o)[i] * ey[i] for i in range(3))] for v in verts]
    xmin = min(p[0] for p in plane)
    ymin = min(p[1] for p in plane)
    xmax = max(p[0] for p in plane)
    ymax = max(p[1] for p in plane)
    # Texel (i, j) covers u in [i, i+1): x = xmin + (u + horz) * incr.
    i0 = math.floor((xmin - xmin) / incr - horz)
    i1 = math.ceil((xmax - xmin) / incr - horz)
    j0 = math.floor((ymin - ymin) / incr - vert)
    j1 = math.ceil((ymax - ymin) / incr - vert)
    for j in range(j0, j1):
        ya, yb = ymin + (j + vert) * incr, ymin + (j + 1 + vert) * incr
        band = clip(clip(plane, 1, ya, True), 1, yb, False)
        if len(band) < 3:
            continue
        for i in range(i0, i1):
            c = tex[j % size][i % size]
            if c is None:
                continue
            xa, xb = xmin + (i + horz) * incr, xmin + (i + 1 + horz) * incr
            cell = clip(clip(band, 0, xa, True), 0, xb, False)
            if len(cell) < 3:
                continue
            world = [[round(o[k] + p[0] * ex[k] + p[1] * ey[k], 9) for k in range(3)] for p in cell]
            out.write(json.dumps({"vertices": world, "color": c}, separators=(",", ":")) + "\n")


def main():
    pat_dir, incr = sys.argv[1], float(sys.argv[2])
    pyr = read_pat(pat_dir + "/pyr.pat")
    chex = read_pat(pat_dir + "/chex.pat")
    out = sys.stdout
    plain = [[-500, 0, 0], [500, 0, 0], [500, 0, -800], [-500, 0, -800]]
    partition(plain, chex, 25.0, 0, 0, out)
    h = 142.2
    faces = [
        [[100, 0, 100], [100, 0, -100], [0, h, 0]],
        [[100, 0, -100], [-100, 0, -100], [0, h, 0]],
        [[-100, 0, 100], [100, 0, 100], [0, h, 0]],
        [[-100, 0, -100], [-100, 0, 100], [0, h, 0]],
    ]
    for f in faces:
        f = [[v[0], v[1], v[2] - 500.0] for v in f]  # translate(0, 0, -500)
        partition(f, pyr, incr, -5, 0, out)


main()
