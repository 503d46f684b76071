#!/usr/bin/env python3
"""Fuzzes polyfill3 with polygons off their plane within --planarity-tol
(docs/polyfill3.md, "Inputs off their plane are projected along the readers'
axis"): every stream polyfill3 writes for an input scene-render takes must be
taken by scene-render too.

    polyfill3_fuzz.py [--bin DIR] [--baseline DIR] [--work DIR] [--jobs J] [RUN ...]

RUN is GENERATOR:SEED:N[:TOL] (TOL default 1e-6, polyfill3's default
--planarity-tol): N inputs drawn by GENERATOR from random.Random(SEED). The
generators are the two review fuzzers docs/polyfill3.md quotes, kept draw for
draw so a seed gives the same inputs as it gave them:

- `shapes` (the review's `fuzz.py SEED N TOL`): stars, stars and triangles
  with a doubled vertex (pinches), combs, notches, two tips, slivers, short
  edges, vertices near another edge; turned, tilted (normals mostly near a
  body diagonal or a tie between two axes), 1e-3 to 1e4 in size, up to 1e7
  from the origin; each vertex lifted off the plane by up to half of TOL of
  the size.
- `tie`, `ulpnear`, `level`, `many`, `mix` (the review's `fuzz2.py SEED N TOL
  KIND`): normals within 1e-13 to 1e-5 of a tie between two or three axes;
  vertices within ulps (or TOL) of another edge; level polygons (z the
  same); stars of 150 to 600 vertices; a mix of the four. 1e5.5 to 1e7 from
  the origin.

Each input is written as a one-record stream naming bench/polyfill3_fuzz/'s
solid.pat (64x64, one colour) or four.pat (64x64, 16 colours), the reviews'
own pattern files, and rendered by scene-render (32x32); an input it
refuses (crosses or touches itself as written, say) is not counted further.
Each input taken is cut by polyfill3 plain, with --merge and with
--merge=blocks, and each stream is rendered by scene-render. With
--baseline, the baseline build's polyfill3 and scene-render do the same, and
the two builds' streams are compared byte for byte. Which inputs were
projected along the axis the binaries do not say; an input whose streams
differ from the baseline's is one the cut changed for (the docs take those
as projected along the axis).

Prints a Markdown table, one row per RUN and a total: inputs drawn, inputs
scene-render takes, polyfill3's refusals (not planar), streams scene-render
refused (this build, and the baseline), and with a baseline the inputs
whose streams both builds wrote and scene-render took, and of those the ones
with the same bytes and with different bytes. Each count is per input and
cut; where the three cuts' counts differ, the cell shows them as
plain/--merge/--merge=blocks. Exits 1 if scene-render refused any stream of
the build under test, or polyfill3 of the build under test refused an input
for anything but not being planar (or failed, or took over 120 s); each such
input is written to WORK/fails/ with the messages, and listed on stderr.

The default RUNs are those of the docs' figures (seeds 60 to 65): 4,600
inputs, about a minute on 2 cores with one build, two with a baseline
(bench/RESULTS-polyfill3-fuzz.md). Standard library only. Driven by
bench/polyfill3_fuzz.sh.
"""
import argparse
import hashlib
import json
import math
import multiprocessing
import os
import random
import shutil
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
PATDIR = os.path.join(ROOT, "bench", "polyfill3_fuzz")
PATS = [os.path.join(PATDIR, "solid.pat"), os.path.join(PATDIR, "four.pat")]
MODES = [[], ["--merge"], ["--merge=blocks"]]
DEFAULT_RUNS = ["shapes:64:700:1e-6", "shapes:65:500:0.01", "tie:60:1000:1e-6",
                "ulpnear:61:1000:1e-6", "level:62:600:1e-6", "mix:63:800:0.1"]
TIMEOUT = 120


# ---- generator `shapes` (the review's fuzz.py) -----------------------------

def logu(r, a, b):
    return 10 ** r.uniform(a, b)


def star(r, k=None):
    k = k or r.randint(3, 10)
    angs = sorted(r.uniform(0, 2 * math.pi) for _ in range(k))
    return [(math.cos(a) * r.uniform(0.2, 1), math.sin(a) * r.uniform(0.2, 1)) for a in angs]


def gap(r, T):
    # near the lift scale (T of the size) mostly; sometimes far smaller/larger
    c = r.random()
    if c < 0.6:
        return T * r.uniform(0.0, 4.0)
    return T * logu(r, -3, 1.5)


def pinch(r, p, T):
    i = r.randrange(len(p))
    a = r.uniform(0, 2 * math.pi)
    g = gap(r, T)
    q = p[:i + 1] + [(p[i][0] + g * math.cos(a), p[i][1] + g * math.sin(a))] + p[i + 1:]
    return q, [i, i + 1]


def shape(r, T):
    kind = r.choice(["star", "starpinch", "quadpinch", "comb", "notch", "twotips",
                     "sliver", "shortedges", "nearedge"])
    hot = []
    if kind == "star":
        p = star(r)
    elif kind == "starpinch":
        p, hot = pinch(r, star(r), T)
    elif kind == "quadpinch":
        p, hot = pinch(r, star(r, 3), T)  # triangle + doubled vertex = quad
    elif kind == "comb":
        t = r.randint(2, 6)
        g = gap(r, T)
        w = 1.0 / t
        p = [(0, 0), (1, 0), (1, 1)]
        for j in range(t - 1, 0, -1):
            x = j * w
            p += [(x + g / 2, 1), (x + g / 2 * r.choice([1, 0, -1]), 0.2 + r.uniform(0, 0.1)), (x - g / 2, 1)]
        p += [(0, 1)]
    elif kind == "notch":
        g = gap(r, T)
        x = r.uniform(0.2, 0.8)
        hw = r.uniform(0.001, 0.2)
        tipx = x + r.choice([0, r.uniform(-0.5, 0.5)])
        p = [(0, 0), (1, 0), (1, 1), (x + hw, 1), (tipx, g * r.choice([1, -1, 0.5])), (x - hw, 1), (0, 1)]
        hot = [4, 0, 1]
    elif kind == "twotips":
        g = gap(r, T)
        x = r.uniform(0.2, 0.8)
        hw = r.uniform(0.001, 0.2)
        y = r.uniform(0.3, 0.7)
        dx = r.choice([0, g, r.uniform(-1, 1) * g])
        p = [(0, 0), (x - hw, 0), (x + dx, y - g / 2), (x + hw, 0), (1, 0), (1, 1),
             (x + hw, 1), (x, y + g / 2), (x - hw, 1), (0, 1)]
        hot = [2, 7]
    elif kind == "sliver":
        w = gap(r, T) * r.choice([1, 10, 100])
        L = 1.0
        if r.random() < 0.5:
            p = [(0, 0), (L, 0), (L * r.uniform(0.2, 0.8), w)]
        else:
            p = [(0, 0), (L, 0), (L * r.uniform(0.5, 1.0), w), (L * r.uniform(0, 0.5), w * r.uniform(0.5, 1.5))]
    elif kind == "shortedges":
        p = star(r)
        for _ in range(r.randint(1, 4)):
            i = r.randrange(len(p))
            j = (i + 1) % len(p)
            t = r.uniform(0, 1)
            mx = p[i][0] + t * (p[j][0] - p[i][0])
            my = p[i][1] + t * (p[j][1] - p[i][1])
            a = r.uniform(0, 2 * math.pi)
            g = gap(r, T)
            p.insert(i + 1, (mx + g * math.cos(a), my + g * math.sin(a)))
    else:  # nearedge: a star whose one vertex is pulled to near a non-adjacent edge
        p = star(r, r.randint(5, 9))
        n = len(p)
        i = r.randrange(n)
        j = (i + r.randint(2, n - 2)) % n
        k = (j + 1) % n
        t = r.uniform(0.05, 0.95)
        mx = p[j][0] + t * (p[k][0] - p[j][0])
        my = p[j][1] + t * (p[k][1] - p[j][1])
        # toward the centre a little
        cx, cy = -mx, -my
        ln = math.hypot(cx, cy) or 1
        g = gap(r, T) * r.choice([1, -1])
        p[i] = (mx + cx / ln * g, my + cy / ln * g)
        hot = [i, j, k]
    return kind, p, hot


def normal(r):
    c = r.random()
    if c < 0.4:  # near a body diagonal: flat view shrinks most
        n = [r.choice([-1, 1]) + r.gauss(0, 0.05) for _ in range(3)]
    elif c < 0.6:  # near a tie between two axes
        n = [r.choice([-1, 1]), r.choice([-1, 1]), r.gauss(0, 0.3)]
        r.shuffle(n)
    elif c < 0.7:
        n = [0, 0, 0]
        n[r.randrange(3)] = 1
        n = [x + r.gauss(0, 1e-3) for x in n]
    else:
        n = [r.gauss(0, 1) for _ in range(3)]
    ln = math.sqrt(sum(x * x for x in n))
    return [x / ln for x in n]


def cross(a, b):
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


def basis(n):
    t = [1, 0, 0] if abs(n[0]) < 0.9 else [0, 1, 0]
    u = cross(n, t)
    ln = math.sqrt(sum(x * x for x in u))
    u = [x / ln for x in u]
    return u, cross(n, u)


def gen_shapes(r, T):
    kind, p, hot = shape(r, T)
    n = normal(r)
    u, w = basis(n)
    th = r.uniform(0, 2 * math.pi)
    c, s = math.cos(th), math.sin(th)
    p = [(c * x - s * y, s * x + c * y) for x, y in p]
    if r.random() < 0.5:
        p = p[::-1]
    size = logu(r, -3, 4)
    oc = r.random()
    off = [0, 0, 0] if oc < 0.2 else [r.uniform(-1, 1) * logu(r, 0, 7) for _ in range(3)]
    xs = [q[0] for q in p]
    ys = [q[1] for q in p]
    diag = math.hypot(max(xs) - min(xs), max(ys) - min(ys))  # in-plane diag ~ bbox diag
    amp = T * diag * r.choice([0.45, 0.49, 0.3, 0.5])
    lm = r.random()
    lifts = []
    for i in range(len(p)):
        if lm < 0.4:
            lift = r.uniform(-1, 1)
        elif lm < 0.7:
            lift = (1 if i % 2 else -1)
        else:
            lift = (r.choice([1, -1]) if i in hot else 0)
        lifts.append(lift * amp)
    V = []
    for (x, y), lift in zip(p, lifts):
        V.append([off[k] + size * (u[k] * x + w[k] * y + n[k] * lift) for k in range(3)])
    # rotate list start
    sh = r.randrange(len(V))
    V = V[sh:] + V[:sh]
    pat = {"file": r.choice(PATS), "incr": size * logu(r, -2.3, 0.3),
           "rotate": r.choice([0, 90, 270, 45, r.uniform(0, 360)])}
    if r.random() < 0.3:
        pat["horz"] = r.uniform(0, 1)
        pat["vert"] = r.uniform(0, 1)
    return kind, {"vertices": V, "color": [100, 100, 100], "pattern": pat}


# ---- generators `tie`, `ulpnear`, `level`, `many`, `mix` (fuzz2.py) --------

def notch2(r, g):
    x = r.uniform(0.2, 0.8)
    hw = r.uniform(0.001, 0.2)
    tipx = x + r.choice([0, r.uniform(-0.5, 0.5)])
    return [(0, 0), (1, 0), (1, 1), (x + hw, 1), (tipx, g), (x - hw, 1), (0, 1)]


def nearedge2(r, g, k=None):
    p = star(r, k or r.randint(5, 9))
    n = len(p)
    i = r.randrange(n)
    j = (i + r.randint(2, n - 2)) % n
    k2 = (j + 1) % n
    t = r.uniform(0.05, 0.95)
    mx = p[j][0] + t * (p[k2][0] - p[j][0])
    my = p[j][1] + t * (p[k2][1] - p[j][1])
    cx, cy = -mx, -my
    ln = math.hypot(cx, cy) or 1
    p[i] = (mx + cx / ln * g, my + cy / ln * g)
    return p


def manystar(r):
    k = r.randint(150, 600)
    angs = sorted(r.uniform(0, 2 * math.pi) for _ in range(k))
    rad = [r.uniform(0.3, 1) for _ in range(k)]
    return [(math.cos(a) * q, math.sin(a) * q) for a, q in zip(angs, rad)]


def shape2(r, T, kind):
    # gap: ulps (relative 1e-16..1e-12) or near T
    g = (10 ** r.uniform(-16.5, -12)) if r.random() < 0.6 else T * r.uniform(0, 3)
    g *= r.choice([1, -1, 0.5])
    c = r.random()
    if kind == "many":
        p = manystar(r)
        if r.random() < 0.5:
            n = len(p)
            i = r.randrange(n)
            # pull vertex i to near a non-adjacent edge j,j+1
            j = (i + r.randint(2, min(20, n - 2))) % n
            k2 = (j + 1) % n
            t = r.uniform(0.05, 0.95)
            mx = p[j][0] + t * (p[k2][0] - p[j][0])
            my = p[j][1] + t * (p[k2][1] - p[j][1])
            ln = math.hypot(mx, my) or 1
            p[i] = (mx - mx / ln * g, my - my / ln * g)
        return p
    if c < 0.45:
        return notch2(r, g)
    if c < 0.9:
        return nearedge2(r, g)
    # pinch
    p = star(r)
    i = r.randrange(len(p))
    a = r.uniform(0, 2 * math.pi)
    return p[:i + 1] + [(p[i][0] + g * math.cos(a), p[i][1] + g * math.sin(a))] + p[i + 1:]


def gen_near(r, T, which):
    kind = which if which != "mix" else r.choice(["level", "ulpnear", "tie", "many"])
    p = shape2(r, T, kind)
    th = r.uniform(0, 2 * math.pi)
    c, s = math.cos(th), math.sin(th)
    if kind == "level" and r.random() < 0.3:
        c, s = 1.0, 0.0
    p = [(c * x - s * y, s * x + c * y) for x, y in p]
    if r.random() < 0.5:
        p = p[::-1]
    size = logu(r, -2, 3)
    off = [r.choice([-1, 1]) * logu(r, 5.5, 7) for _ in range(3)]
    if kind == "level":
        z = r.choice([0.0, 0.1, -3.7, off[2], 1e7 + 0.25])
        V = [[off[0] + size * x, off[1] + size * y, z] for x, y in p]
    else:
        if kind == "tie":
            base = [r.choice([-1, 1]) for _ in range(3)]
            if r.random() < 0.5:
                base[r.randrange(3)] *= r.choice([0.0, 1.0])
            n = [b + r.choice([1, -1]) * 10 ** r.uniform(-13, -5) for b in base]
        else:
            n = [r.gauss(0, 1) for _ in range(3)]
        ln = math.sqrt(sum(x * x for x in n))
        n = [x / ln for x in n]
        u, w = basis(n)
        amp = T * r.choice([0.0, 0.0, 1e-6, 0.3, 0.49]) * math.sqrt(2)
        V = []
        for x, y in p:
            lift = r.uniform(-1, 1) * amp
            V.append([off[k] + size * (u[k] * x + w[k] * y + n[k] * lift) for k in range(3)])
    sh = r.randrange(len(V))
    V = V[sh:] + V[:sh]
    pat = {"file": r.choice(PATS), "incr": size * logu(r, -2.0 if kind != "many" else -1.3, 0.3),
           "rotate": r.choice([0, 90, 45, r.uniform(0, 360)])}
    return kind, {"vertices": V, "color": [100, 100, 100], "pattern": pat}


GENERATORS = {"shapes": gen_shapes}
for _w in ["tie", "ulpnear", "level", "many", "mix"]:
    GENERATORS[_w] = (lambda w: lambda r, T: gen_near(r, T, w))(_w)


# ---- running the binaries --------------------------------------------------

def run(cmd):
    """(exit status, last line of stderr); status 99 for a timeout."""
    try:
        p = subprocess.run(cmd, capture_output=True, text=True, timeout=TIMEOUT)
    except subprocess.TimeoutExpired:
        return 99, "timeout"
    err = p.stderr.strip()
    return p.returncode, err.splitlines()[-1] if err else ""


def msgclass(m):
    for key in ["once its vertices are projected", "crosses itself", "not planar", "no area",
                "touches", "same point", "overlap", "too many", "timeout"]:
        if key in m:
            return key
    return m[:80]


def evaluate(task):
    """One input: None if scene-render refuses it, else per cut and build
    (status, class, message, sha256 of the stream)."""
    rec, T, builds, work = task
    with tempfile.TemporaryDirectory(dir=work) as d:
        inp = os.path.join(d, "in.json")
        with open(inp, "w") as f:
            f.write(json.dumps(rec) + "\n")
        rc, _ = run([os.path.join(builds[0][1], "scene-render"), "--size", "32x32", inp,
                     "-o", os.path.join(d, "in.png")])
        if rc != 0:
            return None
        out = []
        for mode in MODES:
            res = []
            for _, bindir in builds:
                cells = os.path.join(d, "cells.ndjson")
                if os.path.exists(cells):
                    os.remove(cells)
                tol = ["--planarity-tol", repr(T)] if T != 1e-6 else []
                rc, m = run([os.path.join(bindir, "polyfill3")] + tol + mode + [inp, "-o", cells])
                if rc != 0:
                    res.append(("pf_refused", msgclass(m), m, None))
                    continue
                rc2, m2 = run([os.path.join(bindir, "scene-render"), "--size", "32x32", cells,
                               "-o", os.path.join(d, "x.png")])
                with open(cells, "rb") as f:
                    digest = hashlib.sha256(f.read()).hexdigest()
                if rc2 == 0:
                    res.append(("ok", "", "", digest))
                else:
                    res.append(("sr_refused", msgclass(m2), m2, digest))
            out.append(res)
        return out


def parse_run(spec):
    parts = spec.split(":")
    if len(parts) not in (3, 4) or parts[0] not in GENERATORS:
        raise argparse.ArgumentTypeError(
            f"{spec!r}: expected GENERATOR:SEED:N[:TOL], GENERATOR one of {', '.join(GENERATORS)}")
    return parts[0], int(parts[1]), int(parts[2]), float(parts[3]) if len(parts) == 4 else 1e-6


def cell(values):
    """A count over the three cuts: one number where they agree."""
    if len(set(values)) == 1:
        return f"{values[0]:,}"
    return "/".join(f"{v:,}" for v in values)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("runs", nargs="*", type=parse_run, metavar="RUN",
                    help="GENERATOR:SEED:N[:TOL] (default: " + " ".join(DEFAULT_RUNS) + ")")
    target = os.environ.get("CARGO_TARGET_DIR", os.path.join(ROOT, "target"))
    ap.add_argument("--bin", default=os.path.join(target, "release"),
                    help="the build under test's binaries (default: %(default)s)")
    ap.add_argument("--baseline", help="another build's binaries, to compare against")
    ap.add_argument("--work", help="scratch and fails/ directory (default: a temporary one)")
    ap.add_argument("--jobs", type=int, default=os.cpu_count() or 1)
    a = ap.parse_args()
    runs = a.runs or [parse_run(s) for s in DEFAULT_RUNS]
    builds = [("this build", os.path.abspath(a.bin))]
    if a.baseline:
        builds.append(("baseline", os.path.abspath(a.baseline)))
    for _, d in builds:
        for tool in ("polyfill3", "scene-render"):
            if not os.access(os.path.join(d, tool), os.X_OK):
                sys.exit(f"polyfill3_fuzz: no {tool} in {d}")
    work = a.work or tempfile.mkdtemp(prefix="polyfill3-fuzz-")
    scratch = os.path.join(work, "scratch")
    fails = os.path.join(work, "fails")
    os.makedirs(scratch, exist_ok=True)
    os.makedirs(fails, exist_ok=True)

    base = len(builds) > 1
    head = ["generator", "seed", "tol", "inputs", "scene-render takes",
            "polyfill3: not planar", "refused by scene-render"]
    if base:
        head += ["baseline: not planar", "baseline: refused by scene-render", "both read",
                 "same bytes", "different bytes"]
    rows = []
    totals = None
    bad = []
    started = time.monotonic()
    with multiprocessing.Pool(a.jobs) as pool:
        for gname, seed, n, T in runs:
            r = random.Random(seed)
            drawn = [GENERATORS[gname](r, T) for _ in range(n)]
            results = pool.map(evaluate, [(rec, T, builds, scratch) for _, rec in drawn], chunksize=4)
            taken = sum(o is not None for o in results)
            # per cut: [not planar, refused (this), refused (baseline), both read, same, different,
            # not planar (baseline)]
            c = [[0] * 7 for _ in MODES]
            for i, ((kind, rec), o) in enumerate(zip(drawn, results)):
                if o is None:
                    continue
                for m, res in enumerate(o):
                    this = res[0]
                    c[m][0] += this[0] == "pf_refused" and this[1] == "not planar"
                    c[m][1] += this[0] == "sr_refused"
                    if base:
                        old = res[1]
                        c[m][2] += old[0] == "sr_refused"
                        c[m][6] += old[0] == "pf_refused" and old[1] == "not planar"
                        if this[0] == "ok" and old[0] == "ok":
                            c[m][3] += 1
                            c[m][4] += this[3] == old[3]
                            c[m][5] += this[3] != old[3]
                    unexpected = this[0] == "sr_refused" or (
                        this[0] == "pf_refused" and this[1] != "not planar")
                    if unexpected:
                        mode = " ".join(MODES[m]) or "plain"
                        fn = os.path.join(fails, f"{gname}-{seed}-{T}-{i}-{mode.strip('-')}.json")
                        with open(fn, "w") as f:
                            json.dump({"generator": gname, "kind": kind, "seed": seed, "index": i,
                                       "tol": T, "cut": mode, "record": rec,
                                       "builds": [[b[0], b[1], x[:3]] for b, x in zip(builds, res)]}, f)
                        bad.append(f"{gname}:{seed} input {i} ({kind}), {mode}: {this[2]} ({fn})")
            cols = [0, 1] + ([6, 2, 3, 4, 5] if base else [])
            row = [n, taken] + [[c[m][k] for m in range(len(MODES))] for k in cols]
            rows.append([gname, str(seed), f"{T:g}"] + [row[0], row[1]] + row[2:])
            if totals is None:
                totals = [0, 0] + [[0] * len(MODES) for _ in cols]
            totals[0] += n
            totals[1] += taken
            for k in range(2, len(row)):
                totals[k] = [x + y for x, y in zip(totals[k], row[k])]
            print(f"polyfill3_fuzz: {gname}:{seed}:{n}:{T:g} done, {time.monotonic() - started:.0f} s",
                  file=sys.stderr)
    elapsed = time.monotonic() - started

    def fmt(row):
        return [x if isinstance(x, str) else cell(x) if isinstance(x, list) else f"{x:,}" for x in row]
    print("| " + " | ".join(head) + " |")
    print("|---|---:|---:|" + "---:|" * (len(head) - 3))
    for row in rows:
        print("| " + " | ".join(fmt(row)) + " |")
    print("| **total** | | | " + " | ".join(f"**{x}**" for x in fmt(totals)) + " |")
    print()
    print(f"Each count is per input and cut (plain, --merge, --merge=blocks: one number where the "
          f"three agree). Build under test: {builds[0][1]}"
          + (f"; baseline: {builds[1][1]}" if base else "")
          + f". {elapsed:.0f} s with {a.jobs} jobs.")
    for line in bad:
        print("polyfill3_fuzz: FAILED: " + line, file=sys.stderr)
    if bad:
        print(f"polyfill3_fuzz: {len(bad)} cuts failed (a stream scene-render refused, or "
              f"polyfill3 refusing other than not planar); each input is the \"record\" of its "
              f"file in {fails}", file=sys.stderr)
        sys.exit(1)
    if not a.work:
        shutil.rmtree(work)


if __name__ == "__main__":
    main()
