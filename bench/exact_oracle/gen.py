#!/usr/bin/env python3
"""Seeded random scenes for the exact-oracle comparison (bench/exact_oracle).

Each kind is a function (rng, W, H, n) -> list of stream records (flat-coloured
polygons, 8-bit sRGB colours) aimed at one hard case of exact area
antialiasing: interpenetrating tilted triangles, slivers, shared edges and
fans, vertices on pixel corners, huge and nearly parallel polygons, polygons
crossing the z = +-1 clip planes, concave and many-vertex polygons,
collinear and repeated vertices, deep piles over a few pixels.  Coordinates
are mostly dyadic rationals (exact in f64 and in the stream's JSON), so the
scene the renderer reads is the scene the oracle integrates.

make(kind, seed, W, H, n) is deterministic in its arguments; KINDS lists the
kinds in the order the driver runs them.
"""
import json
import math
import random


def dy(v, bits=10):
    """Round to a dyadic rational with `bits` fractional bits (exact in f64)."""
    s = 1 << bits
    return round(v * s) / s


def col(rng):
    return [rng.randint(0, 255) for _ in range(3)]


def tri_rec(vs, c):
    return {"vertices": [list(v) for v in vs], "color": c}


def plane_pts(rng, pts2, zlo=-1.0, zhi=1.0, bits=20):
    """Give 2D points z on a random plane, dyadic coefficients so z is exact."""
    # choose z at the points independently -> a triangle is always planar
    return [(x, y, dy(rng.uniform(zlo, zhi), bits)) for (x, y) in pts2]


def tilted(rng, W, H, n, *z_range):
    """Triangles over the frame and a little past it, on random planes
    (depths in `z_range`, plane_pts's default when not given)."""
    recs = []
    for _ in range(n):
        pts = [(dy(rng.uniform(-4, W + 4)), dy(rng.uniform(-4, H + 4))) for _ in range(3)]
        recs.append(tri_rec(plane_pts(rng, pts, *z_range), col(rng)))
    return recs


def small_tilted(rng, W, H, n):
    recs = []
    for _ in range(n):
        cx, cy = rng.uniform(0, W), rng.uniform(0, H)
        r = rng.uniform(0.3, 6)
        pts = [(dy(cx + rng.uniform(-r, r), 12), dy(cy + rng.uniform(-r, r), 12)) for _ in range(3)]
        recs.append(tri_rec(plane_pts(rng, pts), col(rng)))
    return recs


def slivers(rng, W, H, n):
    recs = []
    for _ in range(n):
        a = (dy(rng.uniform(0, W), 16), dy(rng.uniform(0, H), 16))
        b = (dy(rng.uniform(0, W), 16), dy(rng.uniform(0, H), 16))
        t = rng.uniform(0, 1)
        w = 10 ** rng.uniform(-4, -1)
        dx, dyy = b[0] - a[0], b[1] - a[1]
        L = math.hypot(dx, dyy) or 1
        c = (dy(a[0] + t * dx - dyy / L * w, 20), dy(a[1] + t * dyy + dx / L * w, 20))
        recs.append(tri_rec(plane_pts(rng, [a, b, c]), col(rng)))
    # some background-sized tilted triangles to interact with
    recs += tilted(rng, W, H, max(1, n // 3))
    rng.shuffle(recs)
    return recs


def mesh(rng, W, H, k, jitter, grid_on_pixels, tiltz=True, same_color=False, z0=None):
    """k x k grid of quads split into triangles over the frame (+margin),
    vertices jittered; z from a plane (shared edges exact) or per-vertex."""
    xs = [-2 + (W + 4) * t / k for t in range(k + 1)]
    ys = [-2 + (H + 4) * t / k for t in range(k + 1)]
    P = {}
    if tiltz:
        a, b = dy(rng.uniform(-0.02, 0.02), 16), dy(rng.uniform(-0.02, 0.02), 16)
        c = dy(rng.uniform(-0.3, 0.3), 16) if z0 is None else z0
    for u in range(k + 1):
        for v in range(k + 1):
            x, y = xs[u], ys[v]
            if 0 < u < k and 0 < v < k and jitter:
                x += rng.uniform(-jitter, jitter)
                y += rng.uniform(-jitter, jitter)
            if grid_on_pixels:
                x, y = round(x * 2) / 2, round(y * 2) / 2
            else:
                x, y = dy(x), dy(y)
            if tiltz:
                z = a * x + b * y + c  # dyadic, exact in f64
            else:
                z = dy(rng.uniform(-0.9, 0.9), 20)
            P[u, v] = (x, y, z)
    recs = []
    c0 = col(rng)
    for u in range(k):
        for v in range(k):
            p00, p10, p01, p11 = P[u, v], P[u + 1, v], P[u, v + 1], P[u + 1, v + 1]
            if rng.random() < 0.5:
                t1, t2 = [p00, p10, p11], [p00, p11, p01]
            else:
                t1, t2 = [p00, p10, p01], [p10, p11, p01]
            for t in (t1, t2):
                recs.append(tri_rec(t, c0 if same_color else col(rng)))
    return recs


def shared(rng, W, H, n):
    k = max(2, int(math.sqrt(n / 2)))
    recs = mesh(rng, W, H, k, jitter=(W / k) * 0.3, grid_on_pixels=False,
                tiltz=rng.random() < 0.5, same_color=rng.random() < 0.3)
    recs += mesh(rng, W, H, 2, jitter=3, grid_on_pixels=False, tiltz=True)
    return recs


def fan(rng, W, H, n):
    cx, cy = rng.randint(2, W - 2) + rng.choice([0, 0.5]), rng.randint(2, H - 2) + rng.choice([0, 0.5])
    R = max(W, H) * 0.6
    recs = []
    cz = dy(rng.uniform(-0.5, 0.5), 16)
    angs = sorted(rng.uniform(0, 2 * math.pi) for _ in range(n))
    pts = [(round((cx + R * math.cos(t)) * 2) / 2, round((cy + R * math.sin(t)) * 2) / 2) for t in angs]
    zs = [dy(rng.uniform(-1, 1), 16) for _ in pts]
    same = rng.random() < 0.3
    c0 = col(rng)
    for k in range(n):
        a, b = pts[k], pts[(k + 1) % n]
        if a == b:
            continue
        recs.append(tri_rec([(cx, cy, cz), (a[0], a[1], zs[k]), (b[0], b[1], zs[(k + 1) % n])],
                            c0 if same else col(rng)))
    # a crossing tilted triangle
    recs += tilted(rng, W, H, 2)
    return recs


def corners(rng, W, H, n):
    """vertices on pixel corners / edges / centres."""
    recs = []
    for _ in range(n):
        pts = []
        for _ in range(3):
            x = rng.randint(-2, 2 * W + 4) / 2
            y = rng.randint(-2, 2 * H + 4) / 2
            if rng.random() < 0.3:
                x = rng.randint(0, W) + rng.choice([0.25, 0.75])
            pts.append((x, y))
        recs.append(tri_rec(plane_pts(rng, pts, bits=rng.choice([2, 8, 20])), col(rng)))
    return recs


def large(rng, W, H, n):
    recs = []
    for _ in range(n):
        s = 10 ** rng.uniform(3, 7)
        pts = [(dy(rng.uniform(-s, s) + W / 2, 4), dy(rng.uniform(-s, s) + H / 2, 4)) for _ in range(3)]
        recs.append(tri_rec(plane_pts(rng, pts, bits=24), col(rng)))
    recs += small_tilted(rng, W, H, max(2, n // 3))
    rng.shuffle(recs)
    return recs


def parallel(rng, W, H, n):
    """Nearly parallel planes: same slope plus offsets gap, or slopes differing
    slightly so they cross in the frame; gaps >= 1e-6."""
    recs = []
    a, b = dy(rng.uniform(-0.03, 0.03), 20), dy(rng.uniform(-0.03, 0.03), 20)
    for k in range(n):
        pts = [(dy(rng.uniform(-6, W + 6)), dy(rng.uniform(-6, H + 6))) for _ in range(3)]
        da = dy(rng.uniform(-1e-4, 1e-4), 40) if rng.random() < 0.5 else 0.0
        db = dy(rng.uniform(-1e-4, 1e-4), 40) if rng.random() < 0.5 else 0.0
        c = dy(rng.choice([-1, 1]) * 10 ** rng.uniform(-6, -3) * rng.randint(1, 50), 40)
        vs = [(x, y, (a + da) * (x - W / 2) + (b + db) * (y - H / 2) + c) for x, y in pts]
        recs.append(tri_rec(vs, col(rng)))
    return recs


def zclip(rng, W, H, n):
    """As `tilted`, with depths past the view's z = +-1 to be clipped."""
    return tilted(rng, W, H, n, -3, 3)


def concave(rng, W, H, n):
    recs = []
    for _ in range(n):
        cx, cy = rng.uniform(0, W), rng.uniform(0, H)
        m = rng.randint(5, 12)
        angs = sorted(rng.uniform(0, 2 * math.pi) for _ in range(m))
        if len(set(angs)) < m:
            continue
        r0 = rng.uniform(2, W / 2)
        pts = []
        for t in angs:
            r = r0 * rng.uniform(0.3, 1.0)
            pts.append((dy(cx + r * math.cos(t), 8), dy(cy + r * math.sin(t), 8)))
        a, b = dy(rng.uniform(-0.05, 0.05), 8), dy(rng.uniform(-0.05, 0.05), 8)
        c = dy(rng.uniform(-0.2, 0.2), 8)
        vs = [(x, y, a * (x - cx) + b * (y - cy) + c) for x, y in pts]
        recs.append({"vertices": [list(v) for v in vs], "color": col(rng)})
    recs += tilted(rng, W, H, 2)
    return recs


def floats(rng, W, H, n):
    recs = []
    for _ in range(n):
        pts = [(rng.uniform(-4, W + 4), rng.uniform(-4, H + 4)) for _ in range(3)]
        recs.append(tri_rec([(x, y, rng.uniform(-1, 1)) for x, y in pts], col(rng)))
    return recs


def flat2d(rng, W, H, n):
    """2D records at z = 0 (ties: last wins), rects and triangles."""
    recs = []
    for _ in range(n):
        if rng.random() < 0.5:
            recs.append({"rect": [dy(rng.uniform(-2, W + 2), 6) for _ in range(2)] +
                         [dy(rng.uniform(-2, H + 2), 6) for _ in range(2)], "color": col(rng)})
            r = recs[-1]["rect"]
            r[1], r[2] = r[2], r[1]  # x1,y1,x2,y2
            if r[0] == r[2] or r[1] == r[3]:
                recs.pop()
        else:
            pts = [[dy(rng.uniform(-2, W + 2), 8), dy(rng.uniform(-2, H + 2), 8)] for _ in range(3)]
            recs.append({"vertices": pts, "color": col(rng)})
    return recs


def huge(rng, W, H, n):
    """Triangles with integer vertices up to ~2^45 whose edges cross the frame
    (integer coordinates keep the ortho2 projection exact in f64)."""
    recs = []
    for _ in range(n):
        pts = []
        e = rng.randint(20, 45)
        # a point inside-ish the frame, two far away on roughly opposite sides
        ax, ay = rng.uniform(0, W), rng.uniform(0, H)
        t0 = rng.uniform(0, 2 * math.pi)
        for k in range(3):
            t = t0 + k * 2 * math.pi / 3 + rng.uniform(-0.5, 0.5)
            R = 2.0 ** e * rng.uniform(0.5, 1)
            pts.append((float(round(ax + R * math.cos(t))), float(round(ay + R * math.sin(t)))))
        recs.append(tri_rec(plane_pts(rng, pts, bits=20), col(rng)))
    recs += small_tilted(rng, W, H, max(2, n // 3))
    rng.shuffle(recs)
    return recs


def edgehuge(rng, W, H, n):
    """Huge triangles whose one edge passes through the frame at a random slope:
    two far vertices on a line through the frame, the third far away."""
    recs = []
    for _ in range(n):
        e = rng.randint(16, 44)
        ax, ay = rng.uniform(0, W), rng.uniform(0, H)
        t = rng.uniform(0, 2 * math.pi)
        R = 2.0 ** e
        p1 = (float(round(ax + R * math.cos(t))), float(round(ay + R * math.sin(t))))
        p2 = (float(round(ax - R * math.cos(t))), float(round(ay - R * math.sin(t))))
        s = rng.choice([-1, 1])
        p3 = (float(round(ax - s * R * math.sin(t))), float(round(ay + s * R * math.cos(t))))
        recs.append(tri_rec(plane_pts(rng, [p1, p2, p3], bits=20), col(rng)))
    recs += small_tilted(rng, W, H, max(2, n // 3))
    rng.shuffle(recs)
    return recs


def star(rng, cx, cy, r0, m, bits=8):
    angs = sorted(rng.uniform(0, 2 * math.pi) for _ in range(m))
    pts = []
    for t in angs:
        r = r0 * rng.uniform(0.25, 1.0)
        p = (dy(cx + r * math.cos(t), bits), dy(cy + r * math.sin(t), bits))
        if not pts or p != pts[-1]:
            pts.append(p)
    return pts


def zclip_concave(rng, W, H, n):
    """Concave, steeply tilted polygons crossing z = +-1 (clipped)."""
    recs = []
    for _ in range(n):
        cx, cy = rng.uniform(0, W), rng.uniform(0, H)
        pts = star(rng, cx, cy, rng.uniform(3, W), rng.randint(5, 14))
        if len(pts) < 3:
            continue
        a, b = dy(rng.uniform(-0.4, 0.4), 8), dy(rng.uniform(-0.4, 0.4), 8)
        c = dy(rng.uniform(-1, 1), 8)
        recs.append({"vertices": [[x, y, a * (x - W / 2) + b * (y - H / 2) + c] for x, y in pts],
                     "color": col(rng)})
    return recs


def bigpoly(rng, W, H, n):
    """Convex polygons of many vertices (> 64), tilted, interpenetrating."""
    recs = []
    for _ in range(max(2, n // 4)):
        cx, cy = rng.uniform(0, W), rng.uniform(0, H)
        m = rng.randint(65, 300)
        R = rng.uniform(3, W)
        pts = []
        for k in range(m):
            t = 2 * math.pi * k / m
            p = (dy(cx + R * math.cos(t), 12), dy(cy + R * math.sin(t), 12))
            if not pts or p != pts[-1]:
                pts.append(p)
        # convexity may fail slightly after rounding: keep the hull
        pts = hull(pts)
        a, b = dy(rng.uniform(-0.05, 0.05), 10), dy(rng.uniform(-0.05, 0.05), 10)
        c = dy(rng.uniform(-0.3, 0.3), 10)
        recs.append({"vertices": [[x, y, a * (x - cx) + b * (y - cy) + c] for x, y in pts],
                     "color": col(rng)})
    recs += tilted(rng, W, H, n // 2)
    rng.shuffle(recs)
    return recs


def hull(pts):
    pts = sorted(set(pts))
    def cross(o, a, b):
        return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])
    lo, up = [], []
    for p in pts:
        while len(lo) >= 2 and cross(lo[-2], lo[-1], p) <= 0:
            lo.pop()
        lo.append(p)
    for p in reversed(pts):
        while len(up) >= 2 and cross(up[-2], up[-1], p) <= 0:
            up.pop()
        up.append(p)
    return lo[:-1] + up[:-1]


def collinear(rng, W, H, n):
    """Quads/polygons with collinear extra vertices and repeated vertices."""
    recs = []
    for _ in range(n):
        x0, y0 = dy(rng.uniform(-2, W), 6), dy(rng.uniform(-2, H), 6)
        x1, y1 = dy(x0 + rng.uniform(1, W), 6), dy(y0 + rng.uniform(1, H), 6)
        xm = dy((x0 + x1) / 2, 8)
        ym = dy((y0 + y1) / 2, 8)
        pts = [(x0, y0), (xm, y0), (x1, y0), (x1, y0), (x1, ym), (x1, y1), (x0, y1), (x0, y0)]
        if rng.random() < 0.5:
            pts = pts[:-1]
        a, b = dy(rng.uniform(-0.05, 0.05), 10), dy(rng.uniform(-0.05, 0.05), 10)
        c = dy(rng.uniform(-0.5, 0.5), 10)
        recs.append({"vertices": [[x, y, a * x + b * y + c] for x, y in pts], "color": col(rng)})
    recs += tilted(rng, W, H, 3)
    return recs


def dense(rng, W, H, n):
    """Many triangles piled over a small frame (deep tiles, overtakes)."""
    recs = []
    for _ in range(n):
        pts = [(dy(rng.uniform(-1, W + 1), 12), dy(rng.uniform(-1, H + 1), 12)) for _ in range(3)]
        recs.append(tri_rec(plane_pts(rng, pts), col(rng)))
    return recs


def dense_flat(rng, W, H, n):
    """Many flat (constant z) triangles at distinct depths piled over a small frame."""
    recs = []
    for _ in range(n):
        pts = [(dy(rng.uniform(-1, W + 1), 12), dy(rng.uniform(-1, H + 1), 12)) for _ in range(3)]
        z = dy(rng.uniform(-1, 1), 16)
        recs.append(tri_rec([(x, y, z) for x, y in pts], col(rng)))
    return recs


KINDS = {
    'tilted': tilted, 'small_tilted': small_tilted, 'slivers': slivers, 'shared': shared,
    'fan': fan, 'corners': corners, 'large': large, 'parallel': parallel, 'zclip': zclip,
    'concave': concave, 'floats': floats, 'flat2d': flat2d, 'huge': huge,
    'edgehuge': edgehuge, 'zclip_concave': zclip_concave, 'bigpoly': bigpoly,
    'collinear': collinear, 'dense': dense, 'dense_flat': dense_flat,
}


def degenerate(rec):
    vs = rec.get("vertices")
    if not vs:
        return False
    if len(vs) == 3:
        (x0, y0, *_), (x1, y1, *_), (x2, y2, *_) = vs
        return (x1 - x0) * (y2 - y0) - (x2 - x0) * (y1 - y0) == 0
    return False


def make(kind, seed, W, H, n):
    rng = random.Random(seed)
    recs = [r for r in KINDS[kind](rng, W, H, n) if not degenerate(r)]
    return recs


def write(recs, path):
    with open(path, 'w') as f:
        for r in recs:
            f.write(json.dumps(r) + '\n')
