#!/usr/bin/env python3
"""Exact reference for `scene-render --aa exact` in its default 2D view.

Written from the project's documentation only (README.md, docs/rendering.md,
docs/stream-format.md, docs/camera.md), not from the Rust code: it shares no
code, no algorithm and no floating-point arithmetic with the renderer, so
where the two agree they agree independently.

What it renders: flat-coloured polygon records (`vertices`, or a 2D `rect`)
of an NDJSON or JSON-array stream, in the default view ortho2(0, W, 0, H),
near -1, far 1, no lighting, no textures.  The semantics it implements, as
the docs state them:

  * screen x = world x, screen y = world y (pixel units, y up, origin at the
    lower left); pixel (i, j), counted from the lower left, is the square
    [i, i+1] x [j, j+1].  PNG row 0 is the top row (PNG row r is j = H-1-r);
    PFM rows go bottom to top.
  * z_clip = -z_eye = -z; a point is visible when near <= z_clip <= far,
    i.e. when z is in [-1, 1] (polygons are clipped there).  Nearness is
    q = -z_clip = z for parallel views, so larger z is nearer; it is affine
    in screen space (the polygon's plane, fitted by Newell's method).
  * The nearer polygon wins; on an exact tie (coplanar) the later record
    wins.  With `tie=True`, nearness gaps within 1e-9 (1 + |z|) count as
    ties too (docs/rendering.md, "Visibility and ties"): the tie-aware model.
  * A pixel is sum(area * colour) + (1 - covered area) * background, in linear
    light; 8-bit colours are decoded with the sRGB formula.
  * 8-bit output is the code nearest to 255 * sRGB(value).

How: each pixel is cut into trapezoids by every polygon edge, every z = +-1
line and every equal-nearness line of two polygons (all clipped to the pixel
square, all intersections found), in exact rationals (gmpy2.mpq, or
fractions.Fraction without gmpy2); the polygon nearest at each trapezoid's
centre takes its whole area.  Colours are summed in mpmath at 60 digits.

Usage (one scene, the whole frame):
  oracle.py scene.ndjson W H [--background r,g,b] > exact.json
Output JSON: {"W", "H", "lin": [[r, g, b] per pixel as decimal strings, rows
bottom to top], "code": [8-bit codes], "margin": [...]}, where margin is the
distance (in 8-bit code units) of 255 * sRGB(value) from the nearest rounding
boundary k + 0.5.
"""
import json
import sys

try:
    from gmpy2 import mpq as Q
except ImportError:  # pragma: no cover
    from fractions import Fraction as Q

import mpmath

mpmath.mp.dps = 60
ZERO = Q(0)
ONE = Q(1)
HALF = Q(1, 2)


def srgb_to_linear(code):
    c = mpmath.mpf(code) / 255
    if c <= mpmath.mpf("0.04045"):
        return c / mpmath.mpf("12.92")
    return ((c + mpmath.mpf("0.055")) / mpmath.mpf("1.055")) ** mpmath.mpf("2.4")


def linear_to_srgb(l):
    if l <= 0:
        return mpmath.mpf(0)
    if l >= 1:
        return mpmath.mpf(1)
    if l <= mpmath.mpf("0.0031308"):
        return l * mpmath.mpf("12.92")
    return mpmath.mpf("1.055") * l ** (1 / mpmath.mpf("2.4")) - mpmath.mpf("0.055")


def encode8(l):
    """(code, margin): nearest code, distance of 255*s from nearest k+0.5."""
    s = linear_to_srgb(l) * 255
    code = int(mpmath.floor(s + mpmath.mpf(0.5)))
    code = max(0, min(255, code))
    fl = mpmath.floor(s)
    margin = abs(s - fl - mpmath.mpf(0.5))
    return code, margin


class Poly:
    def __init__(self, idx, verts, color):
        self.idx = idx
        # drop consecutive duplicates (incl. closing repeat)
        vs = []
        for v in verts:
            if not vs or vs[-1] != v:
                vs.append(v)
        if len(vs) > 1 and vs[0] == vs[-1]:
            vs.pop()
        self.v = vs
        self.color = color  # linear mpf triple
        # Newell normal, exact
        nx = ny = nz = ZERO
        n = len(vs)
        for k in range(n):
            x0, y0, z0 = vs[k]
            x1, y1, z1 = vs[(k + 1) % n]
            nx += (y0 - y1) * (z0 + z1)
            ny += (z0 - z1) * (x0 + x1)
            nz += (x0 - x1) * (y0 + y1)
        self.ok = nz != 0
        if self.ok:
            cx = sum((p[0] for p in vs), ZERO) / n
            cy = sum((p[1] for p in vs), ZERO) / n
            cz = sum((p[2] for p in vs), ZERO) / n
            # nx x + ny y + nz z = d  ->  z = a x + b y + c
            d = nx * cx + ny * cy + nz * cz
            self.a = -nx / nz
            self.b = -ny / nz
            self.c = d / nz
        xs = [p[0] for p in vs]
        ys = [p[1] for p in vs]
        self.bb = (min(xs), min(ys), max(xs), max(ys))
        self.edges = [(vs[k][0], vs[k][1], vs[(k + 1) % n][0], vs[(k + 1) % n][1]) for k in range(n)]

    def z(self, x, y):
        return self.a * x + self.b * y + self.c

    def inside(self, x, y):
        # crossing number; point is never on the boundary by construction
        c = False
        for (x0, y0, x1, y1) in self.edges:
            if (y0 > y) != (y1 > y):
                xi = x0 + (y - y0) * (x1 - x0) / (y1 - y0)
                if xi > x:
                    c = not c
        return c


def clip_seg(x0, y0, x1, y1, X0, Y0, X1, Y1):
    """Liang-Barsky clip of a segment to the closed box; None or the segment."""
    dx = x1 - x0
    dy = y1 - y0
    t0, t1 = ZERO, ONE
    for p, q in ((-dx, x0 - X0), (dx, X1 - x0), (-dy, y0 - Y0), (dy, Y1 - y0)):
        if p == 0:
            if q < 0:
                return None
        else:
            r = q / p
            if p < 0:
                if r > t1:
                    return None
                if r > t0:
                    t0 = r
            else:
                if r < t0:
                    return None
                if r < t1:
                    t1 = r
    if t0 > t1:
        return None
    return (x0 + t0 * dx, y0 + t0 * dy, x0 + t1 * dx, y0 + t1 * dy)


def clip_line(A, B, C, X0, Y0, X1, Y1):
    """Line A x + B y + C = 0 clipped to box: ('v', x) or ('s', seg) or None."""
    if B == 0:
        if A == 0:
            return None
        x = -C / A
        if X0 <= x <= X1:
            return ('v', x)
        return None
    # y = m x + k
    m = -A / B
    k = -C / B
    ya = m * X0 + k
    yb = m * X1 + k
    return ('s', clip_seg(X0, ya, X1, yb, X0, Y0, X1, Y1))


# The tie-aware model (tie=True): two polygons whose nearness differs by at
# most TIE_REL * (1 + the larger |z| at the pixel centre) are tied there, and
# the later record wins (docs/rendering.md, "Visibility and ties").  The lines
# where a gap crosses +-tolerance become trapezoid edges too.  Where the rule is
# not transitive and no polygon beats every other one (three near-coplanar
# polygons, each tied with its neighbour), the trapezoid is left to the
# background and noted in CYCLES as (i, j, x, y).
TIE_REL = Q(1, 10**9)
CYCLES = []


def render_pixel(i, j, polys, bg, tie=False):
    """Pixel (i, j): ({record index: exact area}, exact covered area), or
    (bg, 0) when no polygon's box meets the pixel."""
    X0, Y0, X1, Y1 = Q(i), Q(j), Q(i + 1), Q(j + 1)
    rel = [p for p in polys if p.bb[0] < X1 and p.bb[2] > X0 and p.bb[1] < Y1 and p.bb[3] > Y0]
    if not rel:
        return bg, ZERO
    segs = set()  # (x0, x1, m, k)
    xev = {X0, X1}
    tols = {}

    def add_seg(s):
        if s is None:
            return
        xa, ya, xb, yb = s
        if xa == xb:
            if X0 < xa < X1:
                xev.add(xa)
            return
        if xa > xb:
            xa, ya, xb, yb = xb, yb, xa, ya
        m = (yb - ya) / (xb - xa)
        k = ya - m * xa
        segs.add((xa, xb, m, k))
        xev.add(xa)
        xev.add(xb)

    def add_line(r):
        """What clip_line gives: a vertical line's x (an event), a segment,
        or None."""
        if r is None:
            return
        if r[0] == 'v':
            if X0 < r[1] < X1:
                xev.add(r[1])
        else:
            add_seg(r[1])

    add_seg((X0, Y0, X1, Y0))
    add_seg((X0, Y1, X1, Y1))
    for p in rel:
        for e in p.edges:
            add_seg(clip_seg(*e, X0, Y0, X1, Y1))
        for zc in (ONE, -ONE):
            add_line(clip_line(p.a, p.b, p.c - zc, X0, Y0, X1, Y1))
    for u in range(len(rel)):
        for w in range(u + 1, len(rel)):
            p, q = rel[u], rel[w]
            bx0 = max(p.bb[0], q.bb[0]); bx1 = min(p.bb[2], q.bb[2])
            by0 = max(p.bb[1], q.bb[1]); by1 = min(p.bb[3], q.bb[3])
            if bx0 >= bx1 or by0 >= by1:
                continue
            offs = [ZERO]
            if tie:
                cxm, cym = X0 + HALF, Y0 + HALF
                tol = TIE_REL * (1 + max(abs(p.z(cxm, cym)), abs(q.z(cxm, cym))))
                tols[(p.idx, q.idx)] = tol
                ds = [p.z(x, y) - q.z(x, y) for x in (X0, X1) for y in (Y0, Y1)]
                if min(ds) <= tol and max(ds) >= -tol:
                    offs = [ZERO, tol, -tol]
            for off in offs:
                add_line(clip_line(p.a - q.a, p.b - q.b, p.c - q.c - off, X0, Y0, X1, Y1))
    segs = list(segs)
    n = len(segs)
    for u in range(n):
        a0, a1, am, ak = segs[u]
        for w in range(u + 1, n):
            b0, b1, bm, bk = segs[w]
            if am == bm:
                continue
            x = (bk - ak) / (am - bm)
            if x > a0 and x < a1 and x > b0 and x < b1:
                xev.add(x)
    xs = sorted(x for x in xev if X0 <= x <= X1)
    acc = {}  # poly index or -1 -> area
    covered = ZERO
    for t in range(len(xs) - 1):
        xa, xb = xs[t], xs[t + 1]
        xm = (xa + xb) / 2
        wdt = xb - xa
        ys = sorted(s[2] * xm + s[3] for s in segs if s[0] <= xa and s[1] >= xb)
        for u in range(len(ys) - 1):
            h = ys[u + 1] - ys[u]
            if h <= 0:
                continue
            ym = ys[u] + h / 2
            best = None
            bz = None
            cov = []
            for p in rel:  # stream order: later wins exact ties
                if not p.inside(xm, ym):
                    continue
                zz = p.z(xm, ym)
                if zz < -1 or zz > 1:
                    continue
                cov.append((p, zz))
                if best is None or zz >= bz:
                    best, bz = p, zz
            if tie and len(cov) > 1:
                best = None
                for p, zp in cov:
                    ok = True
                    for q, zq in cov:
                        if q is p:
                            continue
                        key = (p.idx, q.idx) if (p.idx, q.idx) in tols else (q.idx, p.idx)
                        tol = tols.get(key, ZERO)
                        d = zp - zq
                        if not (d > tol or (abs(d) <= tol and p.idx > q.idx)):
                            ok = False
                            break
                    if ok:
                        best = p
                        break
                if best is None:
                    CYCLES.append((i, j, xm, ym))
            if best is not None:
                area = wdt * h
                acc[best.idx] = acc.get(best.idx, ZERO) + area
                covered += area
    return acc, covered


def load_scene(path):
    """The stream's polygons, in stream order (records of no projected area dropped)."""
    polys = []
    with open(path) as f:
        txt = f.read()
    recs = []
    if txt.lstrip().startswith('['):
        recs = json.loads(txt)
    else:
        dec = json.JSONDecoder()
        pos = 0
        while True:
            while pos < len(txt) and txt[pos].isspace():
                pos += 1
            if pos >= len(txt):
                break
            r, pos = dec.raw_decode(txt, pos)
            recs.append(r)
    cache = {}
    for idx, r in enumerate(recs):
        if 'vertices' in r:
            vs = [(Q(v[0]), Q(v[1]), Q(v[2]) if len(v) > 2 else ZERO) for v in r['vertices']]
        elif 'rect' in r:
            x1, y1, x2, y2 = [Q(t) for t in r['rect']]
            vs = [(x1, y1, ZERO), (x2, y1, ZERO), (x2, y2, ZERO), (x1, y2, ZERO)]
        else:
            raise SystemExit("unsupported record %d" % idx)
        col = tuple(r['color'])
        lin = []
        for c in col:
            if c not in cache:
                cache[c] = srgb_to_linear(c)
            lin.append(cache[c])
        p = Poly(idx, vs, tuple(lin))
        if p.ok:
            polys.append(p)
    return polys


def pixel_value(i, j, polys, bglin, col, tie=False):
    """Pixel (i, j) as a linear mpf triple."""
    res = render_pixel(i, j, polys, bglin, tie)
    if isinstance(res[0], tuple):
        return res[0]
    acc, covered = res
    pix = []
    for ch in range(3):
        v = mpmath.mpf(0)
        for idx, a in acc.items():
            v += mpmath.mpf(a.numerator) / mpmath.mpf(a.denominator) * col[idx][ch]
        un = ONE - covered
        v += mpmath.mpf(un.numerator) / mpmath.mpf(un.denominator) * bglin[ch]
        pix.append(v)
    return tuple(pix)


def render(path, W, H, bgcode=(0, 0, 0), tie=False, pixels=None):
    """Rows bottom to top of linear mpf triples (None where not in `pixels`)."""
    polys = load_scene(path)
    bglin = tuple(srgb_to_linear(c) for c in bgcode)
    col = {p.idx: p.color for p in polys}
    out = []
    for j in range(H):
        row = []
        for i in range(W):
            if pixels is not None and (i, j) not in pixels:
                row.append(None)
                continue
            row.append(pixel_value(i, j, polys, bglin, col, tie))
        out.append(row)
    return out


if __name__ == '__main__':
    path, W, H = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
    bg = (0, 0, 0)
    if '--background' in sys.argv:
        bg = tuple(int(t) for t in sys.argv[sys.argv.index('--background') + 1].split(','))
    img = render(path, W, H, bg)
    lin, code, margin = [], [], []
    for row in img:
        for pix in row:
            lin.append([mpmath.nstr(v, 40) for v in pix])
            cm = [encode8(v) for v in pix]
            code.append([c for c, _ in cm])
            margin.append([float(m) for _, m in cm])
    json.dump({"W": W, "H": H, "lin": lin, "code": code, "margin": margin}, sys.stdout)
