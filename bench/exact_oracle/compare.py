#!/usr/bin/env python3
"""Run scene-render on one scene and compare its PNG and PFM with oracle.py.

scene-render is run twice, `--aa exact` being its default antialiasing: once
writing an 8-bit PNG, once a PFM (linear f32).  Both are read here with the
standard library alone (zlib, struct) and checked against the exact value of
every channel of every pixel:

  * the PNG code must be the correctly rounded 8-bit code of the exact value;
  * the PFM value's distance from the exact value is measured in f32 ulps
    (the ulp of the exact value).

Two exact values exist where near-coplanar polygons meet: the pure model
(exact ties only) and the tie-aware one (ties within 1e-9 (1 + |z|), as
docs/rendering.md states).  The pure model is computed everywhere; the
tie-aware one only at the pixels where the pure one disagrees with the
output (a PFM value more than 0.6 ulp away, or a PNG code off).  A PNG code
counts as not correctly rounded unless it equals both models' codes; the
PFM's tie-aware error is taken against the tie-aware value where it was
computed, the pure one elsewhere.

Usage: compare.py SCENE_RENDER scene.ndjson W H  (prints the result as JSON;
the images are written next to the scene).
"""
import json
import os
import struct
import subprocess
import sys
import zlib

import mpmath

sys.dont_write_bytecode = True  # no __pycache__ in the source tree
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import oracle  # noqa: E402


def read_png(path):
    """(w, h, channels, rows top to bottom as bytes) of an 8-bit PNG."""
    with open(path, 'rb') as f:
        data = f.read()
    assert data[:8] == b'\x89PNG\r\n\x1a\n'
    pos = 8
    idat = b''
    while pos < len(data):
        ln = struct.unpack('>I', data[pos:pos + 4])[0]
        typ = data[pos + 4:pos + 8]
        body = data[pos + 8:pos + 8 + ln]
        pos += 12 + ln
        if typ == b'IHDR':
            w, h, bd, ct, _, _, il = struct.unpack('>IIBBBBB', body)
            assert bd == 8 and il == 0, (bd, il)
            ch = {2: 3, 6: 4, 0: 1}[ct]
        elif typ == b'IDAT':
            idat += body
    raw = zlib.decompress(idat)
    stride = w * ch
    rows = []
    prev = bytearray(stride)
    p = 0
    for _ in range(h):
        f = raw[p]
        line = bytearray(raw[p + 1:p + 1 + stride])
        p += 1 + stride
        for x in range(stride):
            a = line[x - ch] if x >= ch else 0
            b = prev[x]
            c = prev[x - ch] if x >= ch else 0
            if f == 1:
                line[x] = (line[x] + a) & 255
            elif f == 2:
                line[x] = (line[x] + b) & 255
            elif f == 3:
                line[x] = (line[x] + (a + b) // 2) & 255
            elif f == 4:
                pp = a + b - c
                pa, pb, pc = abs(pp - a), abs(pp - b), abs(pp - c)
                pr = a if pa <= pb and pa <= pc else (b if pb <= pc else c)
                line[x] = (line[x] + pr) & 255
        rows.append(bytes(line))
        prev = line
    return w, h, ch, rows


def read_pfm(path):
    """(w, h, values) of a little-endian RGB PFM, rows bottom to top."""
    with open(path, 'rb') as f:
        data = f.read()
    parts = data.split(b'\n', 3)
    assert parts[0] == b'PF'
    w, h = [int(t) for t in parts[1].split()]
    scale = float(parts[2])
    assert scale < 0
    vals = struct.unpack('<%df' % (w * h * 3), parts[3][:w * h * 12])
    return w, h, vals


def f32_ulp(x):
    """The f32 ulp at the (positive) value x."""
    return mpmath.mpf(2) ** (mpmath.floor(mpmath.log(x, 2)) - 23)


def run(binary, scene, W, H, extra=(), tag='out', bg=(0, 0, 0)):
    """Render `scene` at W x H with `binary` and compare with the oracle."""
    d = os.path.dirname(scene)
    png = os.path.join(d, tag + '.png')
    pfm = os.path.join(d, tag + '.pfm')
    args = [binary, '--size', '%dx%d' % (W, H)] + list(extra)
    if bg != (0, 0, 0):
        args += ['--background', '%d,%d,%d' % bg]
    r1 = subprocess.run(args + [scene, '-o', png], capture_output=True, text=True)
    r2 = subprocess.run(args + [scene, '-o', pfm], capture_output=True, text=True)
    if r1.returncode or r2.returncode:
        return {'error': r1.stderr + r2.stderr}
    warn = r1.stderr.strip()
    _, _, ch, rows = read_png(png)
    _, _, fv = read_pfm(pfm)
    oracle_img = oracle.render(scene, W, H, bg)

    # The tie-aware model, only where the pure one disagrees with the output.
    flagged = set()
    for j in range(H):
        for i in range(W):
            for c in range(3):
                ex = oracle_img[j][i][c]
                f = fv[(j * W + i) * 3 + c]
                err = abs(mpmath.mpf(f) - ex)
                lim = f32_ulp(ex) * 0.6 if ex > 0 else 0
                if err > lim or rows[H - 1 - j][i * ch + c] != oracle.encode8(ex)[0]:
                    flagged.add((i, j))
    ncyc0 = len(oracle.CYCLES)
    if flagged:
        tie_img = oracle.render(scene, W, H, bg, tie=True, pixels=flagged)
    else:
        tie_img = [[None] * W for _ in range(H)]
    ncyc = len(oracle.CYCLES) - ncyc0

    mism = []
    maxabs = maxrel = maxulp = 0.0
    maxabs_tie = maxulp_tie = 0.0
    minmargin = 1e9
    for j in range(H):
        for i in range(W):
            for c in range(3):
                ex = oracle_img[j][i][c]
                code, margin = oracle.encode8(ex)
                got = rows[H - 1 - j][i * ch + c]
                minmargin = min(minmargin, float(margin))
                f = fv[(j * W + i) * 3 + c]
                tx = tie_img[j][i][c] if tie_img[j][i] is not None else ex
                tcode, _ = oracle.encode8(tx)
                et = abs(mpmath.mpf(f) - tx)
                maxabs_tie = max(maxabs_tie, float(et))
                if tx > 0:
                    maxulp_tie = max(maxulp_tie, float(et / f32_ulp(tx)))
                elif f != 0:
                    maxulp_tie = float('inf')
                if got != code or got != tcode:
                    mism.append({'i': i, 'j': j, 'c': c, 'got': got, 'exact_code': code,
                                 'margin_codes': float(margin), 'lin': mpmath.nstr(ex, 20),
                                 'tie_code': tcode, 'tie_lin': mpmath.nstr(tx, 20),
                                 'pfm': f, 'pfm_code': oracle.encode8(mpmath.mpf(f))[0]})
                err = abs(mpmath.mpf(f) - ex)
                maxabs = max(maxabs, float(err))
                if ex > 0:
                    maxrel = max(maxrel, float(err / ex))
                    maxulp = max(maxulp, float(err / f32_ulp(ex)))
                elif f != 0:
                    maxulp = float('inf')
    return {'mism': mism, 'maxabs': maxabs, 'maxrel': maxrel, 'maxulp': maxulp,
            'minmargin': minmargin, 'warn': warn, 'maxabs_tie': maxabs_tie,
            'maxulp_tie': maxulp_tie, 'cycles': ncyc, 'tie_pixels': len(flagged)}


if __name__ == '__main__':
    binary, scene, W, H = sys.argv[1], sys.argv[2], int(sys.argv[3]), int(sys.argv[4])
    print(json.dumps(run(binary, scene, W, H), indent=1))
