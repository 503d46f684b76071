#!/usr/bin/env python3
"""Driver of the exact-oracle benchmark (bench/exact_oracle.sh).

Generates seeded scenes (gen.py), renders each with scene-render `--aa exact`
to PNG and PFM and compares every channel of every pixel with the exact value
(compare.py, oracle.py), runs the huge-coordinate probe (the known
exception), and prints a Markdown report to stdout; progress goes to stderr.

    run.py SCENE_RENDER WORK [--kinds all|k1,k2,...] [--seeds 4-8]
           [--jobs 2] [--threads 1]

Seeds are an inclusive range.  A scene's frame size, record count and
background follow from its kind and seed alone (scene_params), so a kind and
seed name the same scene in every run.  Scenes, images and results.ndjson
(one JSON line a scene) are written under WORK/exact-oracle-run, which is
emptied first; nothing is written anywhere else.
"""
import argparse
import json
import multiprocessing
import os
import random
import shutil
import sys
import time

sys.dont_write_bytecode = True  # no __pycache__ in the source tree
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import compare  # noqa: E402
import gen  # noqa: E402

# The known exception (docs/rendering.md, "Where exactness holds"): one white
# triangle with vertices near 1e15 over the frame, rendered at 16x16 and 20x20.
HUGE_PROBE = {"vertices": [[-1000000000000003, -3000000000000001, 0],
                           [1000000000000011, 3000000000000027, 0],
                           [3000000000000001, -1000000000000007, 0]],
              "color": [255, 255, 255]}
PROBE_SIDES = (16, 20)

# A PFM value within this many f32 ulps of the exact value is as close as an
# f32 frame computed in f64 can be expected to hold it (0.5 for the rounding
# to f32, a little more for the f64 sums before it).
PFM_ULP_BOUND = 0.6


def scene_params(kind, seed):
    """(W, H, n, background) of a scene: drawn from its kind and seed."""
    rng = random.Random(seed * 1000 + sum(map(ord, kind)))
    W = rng.choice([16, 16, 24, 32])
    H = rng.choice([16, 16, 20, 32])
    n = rng.randint(3, 30)
    if kind.startswith('dense'):
        W = H = rng.choice([6, 8])
        n = rng.randint(15, 40)
    bg = (0, 0, 0) if rng.random() < 0.5 else tuple(rng.randint(0, 255) for _ in range(3))
    return W, H, n, bg


def max_coordinate(recs):
    """The largest |x| or |y| of a scene's vertices."""
    m = 0.0
    for r in recs:
        for v in r.get('vertices', []):
            m = max(m, abs(v[0]), abs(v[1]))
        for t in r.get('rect', []):
            m = max(m, abs(t))
    return m


def run_scene(task):
    """Generate, render and compare one scene; its result as a dict, or None
    when the generator made no records."""
    binary, out, kind, seed, threads = task
    W, H, n, bg = scene_params(kind, seed)
    recs = gen.make(kind, seed, W, H, n)
    if not recs:
        return None
    d = os.path.join(out, '%s-%d' % (kind, seed))
    os.makedirs(d, exist_ok=True)
    scene = os.path.join(d, 'scene.ndjson')
    gen.write(recs, scene)
    t0 = time.time()
    r = compare.run(binary, scene, W, H, extra=['--threads', str(threads)], tag='out', bg=bg)
    r.update(kind=kind, seed=seed, W=W, H=H, n=len(recs), bg=bg,
             maxcoord=max_coordinate(recs), secs=round(time.time() - t0, 1))
    r['nmism'] = len(r.get('mism', []))
    r['mism'] = r.get('mism', [])[:50]
    return r


def progress(r):
    if 'error' in r:
        msg = 'rejected: ' + r['error'].strip().splitlines()[0][:160]
    else:
        msg = 'png off %d, pfm %.3f ulp (tie-aware), margin %.2e' % (
            r['nmism'], r['maxulp_tie'], r['minmargin'])
    print('%s-%d %dx%d n=%d: %s (%.1f s)' % (r['kind'], r['seed'], r['W'], r['H'], r['n'],
                                             msg, r['secs']), file=sys.stderr, flush=True)


def run_probe(binary, out, threads):
    """The huge-coordinate probe at each side of PROBE_SIDES."""
    d = os.path.join(out, 'probe-huge')
    os.makedirs(d, exist_ok=True)
    scene = os.path.join(d, 'scene.ndjson')
    gen.write([HUGE_PROBE], scene)
    rows = []
    for s in PROBE_SIDES:
        r = compare.run(binary, scene, s, s, extra=['--threads', str(threads)], tag='out-%dx%d' % (s, s))
        if 'error' in r:
            raise SystemExit('scene-render failed on the probe: ' + r['error'])
        r['side'] = s
        r['pixels_off'] = len({(m['i'], m['j']) for m in r['mism']})
        rows.append(r)
    return rows


def fmt_ulp(x):
    return 'inf' if x == float('inf') else '%.3f' % x if x < 10 else '%.0f' % x


def report(results, probe, kinds):
    """The Markdown tables (stdout)."""
    print('| kind | scenes | rejected | pixels | channel values | PNG values not correctly rounded '
          '| closest margin (codes) | largest PFM error (f32 ulps, tie-aware) | time (s) |')
    print('|---|---:|---:|---:|---:|---:|---:|---:|---:|')
    tot = dict(scenes=0, rejected=0, pixels=0, values=0, off=0, margin=float('inf'),
               ulp=0.0, secs=0.0)
    for kind in kinds:
        rs = [r for r in results if r['kind'] == kind]
        ok = [r for r in rs if 'error' not in r]
        k = dict(scenes=len(ok), rejected=len(rs) - len(ok),
                 pixels=sum(r['W'] * r['H'] for r in ok),
                 off=sum(r['nmism'] for r in ok),
                 margin=min((r['minmargin'] for r in ok), default=float('inf')),
                 ulp=max((r['maxulp_tie'] for r in ok), default=0.0),
                 secs=sum(r['secs'] for r in rs))
        k['values'] = 3 * k['pixels']
        for key in ('scenes', 'rejected', 'pixels', 'values', 'off', 'secs'):
            tot[key] += k[key]
        tot['margin'] = min(tot['margin'], k['margin'])
        tot['ulp'] = max(tot['ulp'], k['ulp'])
        print('| %s | %d | %d | %d | %d | %d | %s | %s | %.0f |' % (
            kind, k['scenes'], k['rejected'], k['pixels'], k['values'], k['off'],
            '%.2e' % k['margin'] if ok else '-', fmt_ulp(k['ulp']) if ok else '-', k['secs']))
    print()
    print('**Total: %d scenes, %d pixels, %d channel values compared; %d PNG values not '
          'correctly rounded; closest margin to a code boundary %.2e codes; largest PFM error '
          '%s f32 ulps (tie-aware); %d scenes rejected by scene-render; %.0f s of comparisons.**'
          % (tot['scenes'], tot['pixels'], tot['values'], tot['off'], tot['margin'],
             fmt_ulp(tot['ulp']), tot['rejected'], tot['secs']))
    print()
    over = [r for r in results if 'error' not in r and r['maxulp_tie'] > PFM_ULP_BOUND]
    if over:
        print('Scenes with a PFM value more than %.1f f32 ulps from the exact value:' % PFM_ULP_BOUND)
        print()
        for r in over:
            print('- %s seed %d (%dx%d, %d records, vertices up to |%.3g|): %s ulps '
                  '(%.2e absolute), %d PNG values off.' % (
                      r['kind'], r['seed'], r['W'], r['H'], r['n'], r['maxcoord'],
                      fmt_ulp(r['maxulp_tie']), r['maxabs_tie'], r['nmism']))
    else:
        print('Every PFM value compared is within %.1f f32 ulps of the exact value.' % PFM_ULP_BOUND)
    rejected = [r for r in results if 'error' in r]
    if rejected:
        print()
        print('Rejected scenes (scene-render refused the input, nothing to compare): %s.' % ', '.join(
            '%s-%d' % (r['kind'], r['seed']) for r in rejected))
        print('First reason: `%s`' % rejected[0]['error'].strip().splitlines()[0].split('scene.ndjson: ', 1)[-1])
    print()
    print('## Known exception: vertices near 1e15')
    print()
    print('One white triangle with vertices near 1e15 covering the frame, black background '
          '(docs/rendering.md, "Where exactness holds": the projection rounds each vertex '
          'in f64, and vertices near 1e12 and beyond move measurably).')
    print()
    print('| frame | pixels | pixels off (PNG) | PNG values not correctly rounded '
          '| largest PFM error (f32 ulps, tie-aware) | largest PFM error (absolute) |')
    print('|---|---:|---:|---:|---:|---:|')
    for r in probe:
        print('| %dx%d | %d | %d | %d | %s | %.2e |' % (
            r['side'], r['side'], r['side'] ** 2, r['pixels_off'], len(r['mism']),
            fmt_ulp(r['maxulp_tie']), r['maxabs_tie']))


def parse_seeds(s):
    lo, _, hi = s.partition('-')
    return range(int(lo), int(hi or lo) + 1)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split('\n\n')[0])
    ap.add_argument('scene_render', help='the scene-render binary')
    ap.add_argument('work', help='work directory (results go to WORK/exact-oracle-run)')
    ap.add_argument('--kinds', default='all', help="comma-separated kinds, or 'all' (%s)"
                    % ', '.join(gen.KINDS))
    ap.add_argument('--seeds', default='4-8', help='inclusive range, e.g. 4-7')
    ap.add_argument('--jobs', type=int, default=2, help='scenes compared at once')
    ap.add_argument('--threads', type=int, default=1, help="scene-render's --threads")
    a = ap.parse_args()
    kinds = list(gen.KINDS) if a.kinds == 'all' else a.kinds.split(',')
    for k in kinds:
        if k not in gen.KINDS:
            ap.error('unknown kind %r' % k)
    binary = os.path.abspath(a.scene_render)
    out = os.path.join(os.path.abspath(a.work), 'exact-oracle-run')
    shutil.rmtree(out, ignore_errors=True)
    os.makedirs(out)

    tasks = [(binary, out, kind, seed, a.threads) for seed in parse_seeds(a.seeds) for kind in kinds]
    # The deep piles take minutes a scene where most take a second: start them
    # first, so the jobs end together.
    tasks.sort(key=lambda t: not t[2].startswith('dense'))
    results = []
    with multiprocessing.Pool(a.jobs) as pool:
        for r in pool.imap_unordered(run_scene, tasks):
            if r is not None:
                progress(r)
                results.append(r)
    results.sort(key=lambda r: (kinds.index(r['kind']), r['seed']))
    with open(os.path.join(out, 'results.ndjson'), 'w') as f:
        for r in results:
            f.write(json.dumps(r) + '\n')
    print('probe: vertices near 1e15', file=sys.stderr, flush=True)
    probe = run_probe(binary, out, a.threads)
    with open(os.path.join(out, 'probe.ndjson'), 'w') as f:
        for r in probe:
            f.write(json.dumps(r) + '\n')
    report(results, probe, kinds)


if __name__ == '__main__':
    main()
