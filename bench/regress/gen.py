#!/usr/bin/env python3
"""Input generator of the regression corpus (bench/regress/run.sh).

    python3 gen.py ROOT OUT

Writes every generated input under OUT/scenes/<group>/ (and OUT/in/): the
test suite's inline scenes and patterns (tests/cli/*.rs), the bench scripts'
scene generators (imported or executed from bench/), the docs' examples.
Standard library only, fully deterministic (fixed seeds, fixed formatting).
"""
import json
import math
import os
import random
import shutil
import struct
import subprocess
import sys
import zlib

ROOT, OUT = sys.argv[1], sys.argv[2]
SC = os.path.join(OUT, "scenes")
sys.path.insert(0, os.path.join(ROOT, "bench"))


def d(*parts):
    p = os.path.join(SC, *parts)
    os.makedirs(p, exist_ok=True)
    return p


def w(path, text, mode="w"):
    os.makedirs(os.path.dirname(path), exist_ok=True)
    with open(path, mode) as fh:
        fh.write(text)


def jl(records):
    """NDJSON with compact separators (the tests' r#"..."# style)."""
    return "".join(json.dumps(r, separators=(",", ":")) + "\n" for r in records)


def png(path, width, height, f):
    """An 8-bit RGBA PNG, f(x, y) -> (r, g, b, a), y = 0 the top row."""
    raw = b"".join(b"\x00" + bytes(c for x in range(width) for c in f(x, y)) for y in range(height))

    def chunk(tag, data):
        return struct.pack(">I", len(data)) + tag + data + struct.pack(">I", zlib.crc32(tag + data) & 0xFFFFFFFF)

    data = b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 6, 0, 0, 0))
    data += chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b"")
    w(path, data, "wb")


# ---------------------------------------------------------------- patterns
def checker16():
    """tests/cli/util.rs checker16."""
    s = "16 2\n255 0 0\n"
    for parity in (0, 1):
        if parity == 1:
            s += "0 0 255\n"
        for row in range(16):
            word = 0
            for col in range(16):
                st = (col + row) % 2 == parity and not (col == 0 and row == 0)
                word = (word << 1) | int(st)
            s += "%04x\n" % word
    return s


def pattern_from(f, colors):
    """tests/cli/texture.rs pattern_from (16x16)."""
    s = "16 %d\n" % len(colors)
    for i, c in enumerate(colors):
        s += "%d %d %d\n" % tuple(c)
        for r in range(16):
            word = 0
            for col in range(16):
                word = (word << 1) | int(f(col, r) == i)
            s += "%04x\n" % word
    return s


def pattern3():
    return pattern_from(lambda c, r: None if (c, r) == (3, 2) else (c + 2 * r) % 3,
                        [[255, 0, 0], [0, 0, 255], [0, 200, 0]])


QUADRANTS = [[255, 0, 0], [0, 255, 0], [0, 0, 255], [255, 255, 255]]
BANDS = [[255, 0, 0], [0, 255, 0], [0, 0, 255], [255, 255, 0]]


def quadrant_pattern():
    return pattern_from(lambda c, r: (c % 2) + 2 * (r % 2), QUADRANTS)


def write_pat_1(size, transparent):
    """tests/cli/polyfill3.rs write_pat: one colour 200 100 50."""
    s = "%d 1\n200 100 50\n" % size
    for row in range(size):
        words = []
        for wd in range(size // 16):
            bits = 0
            for b in range(16):
                if not transparent(wd * 16 + b, row):
                    bits |= 0x8000 >> b
            words.append("%04x" % bits)
        s += " ".join(words) + "\n"
    return s


def pattern_text(size):
    """tests/cli/stress.rs pattern_text: three colours, canonical."""
    rows = []
    for r in range(size):
        rows.append([((c // 3) + (r // 5)) % 3 for c in range(size)])
    s = "%d 3\n" % size
    for ci, rgb in enumerate([(250, 20, 20), (20, 250, 20), (20, 20, 250)]):
        s += "%d %d %d\n" % rgb
        for row in rows:
            words = []
            for wd in range(0, size, 16):
                bits = 0
                for c in range(wd, wd + 16):
                    bits = (bits << 1) | int(row[c] == ci)
                words.append("%04x" % bits)
            s += " ".join(words) + "\n"
    return s


MAP8 = "STRIPE 8\n0 32 64 96 128 160 192 255\n"
HALF = '{"vertices":[[0,0],[2,0],[1,1],[0,1]],"color":[255,255,255]}'


def tests():
    t = d("t")
    w(f"{t}/c.pat", checker16())
    w(f"{t}/p.pat", pattern3())
    w(f"{t}/q.pat", quadrant_pattern())
    w(f"{t}/b.pat", pattern_from(lambda c, r: c // 4, BANDS))
    w(f"{t}/k.pat", pattern_from(lambda c, r: c // 8 + 2 * (r // 8), QUADRANTS))
    w(f"{t}/l.pat", pattern_from(lambda c, r: c // 4, [[255, 0, 0], [0, 255, 0], [0, 0, 255], [0, 255, 255]]))
    w(f"{t}/w.pat", pattern_from(lambda c, r: None if (c, r) == (0, 0) else (0 if c < 8 else 1),
                                 [[255, 255, 255], [0, 0, 0]]))
    w(f"{t}/checker.pat", pattern_from(lambda c, r: (c + r) % 2, [[230, 230, 230], [20, 20, 120]]))
    w(f"{t}/half.pat", "16 2\n255 0 0\n" + "ff00\n" * 16 + "0 0 255\n" + "00ff\n" * 16)
    w(f"{t}/p1.pat", write_pat_1(16, lambda c, r: False))
    w(f"{t}/p1hole.pat", write_pat_1(16, lambda c, r: c == 1 and r == 0))
    w(f"{t}/p1stripes.pat", write_pat_1(16, lambda c, r: c % 4 == 3))
    w(f"{t}/bad.pat", "16 1\n1 2 300\n")
    w(f"{t}/bad2.pat", "16 1\n")
    w(f"{t}/bad3.pat", "16 1\n1 2 3\nzz\n")
    w(f"{t}/binary.pat", "\x00\x01binary")
    w(f"{t}/empty.pat", "")
    w(f"{t}/brick.pat", open(os.path.join(ROOT, "fixtures/patterns/brick.pat")).read())
    # 48x48 checker (texture_filters.rs mip_filters_work_on_a_non_power_of_two_pattern)
    pat = "48 2\n0 0 0\n"
    rows = lambda odd: "".join("%s %s %s\n" % ((("aaaa" if (r % 2 == 0) ^ odd else "5555"),) * 3) for r in range(48))
    pat += rows(False) + "255 255 255\n" + rows(True)
    w(f"{t}/c48.pat", pat)
    # skips.rs
    dots = "16 1\n240 40 40\n" + "".join("c0c0\n" if r % 8 < 2 else "0000\n" for r in range(16))
    w(f"{t}/dots.pat", dots)
    rws = lambda e, o: "".join((e if r % 4 < 2 else o) + "\n" for r in range(16))
    w(f"{t}/opaque.pat", "16 2\n230 230 230\n" + rws("cccc", "3333") + "20 20 120\n" + rws("3333", "cccc"))
    for size in (16, 64, 256, 1024):
        w(f"{t}/pt{size}.pat", pattern_text(size))

    # maps
    w(f"{t}/m.map", MAP8)
    w(f"{t}/maps/m.map", MAP8)
    w(f"{t}/maps/s.tm", "TRANSLATE\n" + " ".join(str(255 - i) for i in range(256)) + "\n")
    w(f"{t}/maps/short.tm", "TRANSLATE\n1 2 3\n")
    w(f"{t}/maps/odd.map", "STRIPE 6\n1 2 3 4 5 6\n")
    w(f"{t}/short.tm", "TRANSLATE\n1 2 3\n")
    w(f"{t}/odd.map", "STRIPE 6\n1 2 3 4 5 6\n")
    w(f"{t}/odd1000.map", "STRIPE 1000\n")
    w(f"{t}/big.map", "STRIPE 8\n0 1 2 3 4 5 6 300\n")
    shutil.copy(os.path.join(ROOT, "fixtures/stripes/runway.map"), f"{t}/runway.map")

    # scene_render.rs
    w(f"{t}/half.json", HALF)
    w(f"{t}/curves.json", """[{"circle":{"center":[20,15],"radius":11.3},"color":[200,40,10]},
            {"arc":{"center":[30,20],"radius":9,"start":30,"end":300},"color":[10,40,200]},
            {"vertices":[[3,3],[37,5],[20,28]],"color":[250,250,0]}]""")
    s = ""
    for i in range(200):
        x, y = float(i * 37 % 90), float(i * 53 % 60)
        s += '{"vertices":[[%s,%s,%s],[%s,%s,0],[%s,%s,1]],"color":[%d,%d,90]}\n' % (
            x, y, (i % 7) / 10.0, x + 13.5, y, x, y + 9.25, i % 256, (i * 7) % 256)
    w(f"{t}/tris200.json", s)
    w(f"{t}/plain.json", '{"vertices":[[-500,0,0],[500,0,0],[500,0,-800],[-500,0,-800]],"color":[0,200,0]}')
    w(f"{t}/cam.json", """{"lookat":{"eye":[0,100,-5],"center":[0,0,-900],"twist":0},
            "perspective":{"fovy":55,"aspect":1.0,"near":0,"far":1000}}""")
    w(f"{t}/screen.json", """[{"rect":[0,0,4,3],"color":[0,255,0]},
            {"vertices":[[0,0,0.5],[4,0,0.5],[4,3,0.5],[0,3,0.5]],"pattern":{"file":"c.pat","mode":"screen"}}]""")
    w(f"{t}/missingpat.json", '[{"rect":[0,0,5,5],"color":[1,2,3]},{"rect":[0,0,5,5],"pattern":{"file":"nob.pat"}}]')
    w(f"{t}/nan.json", '{"vertices":[[NaN,0],[1,0],[0,1]],"color":[0,0,0]}')
    w(f"{t}/pyramid.json", """[{"vertices":[[-500,0,0],[500,0,0],[500,0,-800],[-500,0,-800]],"color":[40,120,40]},
            {"vertices":[[100,0,-400],[100,0,-600],[0,142.2,-500]],"color":[200,160,90]},
            {"vertices":[[-100,0,-400],[100,0,-400],[0,142.2,-500]],"color":[180,140,80]},
            {"vertices":[[-100,0,-600],[-100,0,-400],[0,142.2,-500]],"color":[160,120,70]}]""")
    tt = math.tan(math.radians(27.5))
    w(f"{t}/textbook.json", '{"view":{"vrp":[0,100,-5],"vpn":[0,-100,-895],"view_up":[0,1,0],'
      '"view_distance":1,"window":[%r,%r,%r,%r],"cop":[0,100,-5],"front":0,"back":1000}}' % (-tt, tt, -tt, tt))
    sq = '{"vertices":[[0,0],[1,0],[1,1],[0,1]],"color":[255,255,255]}'
    w(f"{t}/objects.json",
      '{"object":"sq","records":[%s]}\n'
      '{"object":"two","records":[{"instance":"sq","transform":{"scale":2}},'
      '{"instance":"sq","transform":[{"scale":2},{"translate":[3,0,0]}]}]}\n'
      '{"instance":"two","transform":{"translate":[1,1,0]}}\n' % sq)
    w(f"{t}/copies.json", '{"vertices":[[1,1],[3,1],[3,3],[1,3]],"color":[255,255,255]}\n'
                          '{"vertices":[[4,1],[6,1],[6,3],[4,3]],"color":[255,255,255]}\n')
    w(f"{t}/ghost.json", '{"instance":"ghost"}')
    w(f"{t}/cycle.json", '{"object":"a","records":[{"instance":"a"}]}')
    w(f"{t}/singular.json", '{"object":"a","records":[]} {"instance":"a","transform":{"matrix":[[1,0,0,0],[0,1,0,0],[0,0,0,0],[0,0,0,1]]}}')
    w(f"{t}/shrink.json", '{"object":"a","records":[{"rect":[0,0,1,1],"color":[1,2,3]}]}\n'
                          '{"instance":"a","transform":{"scale":{"start":2,"step":-1}}}')
    s = ""
    for i in range(120):
        a0 = i / 120.0 * math.tau
        a1 = (i + 0.5) / 120.0 * math.tau
        c = "[250,40,40]" if i % 2 == 0 else "[20,200,90]"
        s += '{"vertices":[[256,192],[%r,%r],[%r,%r]],"color":%s}\n' % (
            256.0 + 180.0 * math.cos(a0), 192.0 + 180.0 * math.sin(a0),
            256.0 + 180.0 * math.cos(a1), 192.0 + 180.0 * math.sin(a1), c)
    w(f"{t}/fan120.json", s + '{"rect":[0,0,64,64],"color":[9,9,200]}\n')

    # texture.rs / texture_filters.rs
    SCENE = ('{"vertices":[[-3,-1,-2],[3,-1,-2],[3,-1,-12],[-3,-1,-12]],"color":[200,200,200],"pattern":{"file":"p.pat","incr":0.37,"rotate":10,"horz":0.3,"vert":0.6}}\n'
             '{"vertices":[[-1,-0.5,-4],[1,-0.2,-4.5],[0.5,1.5,-5]],"color":[255,255,0],"pattern":{"file":"p.pat","incr":0.21}}\n'
             '{"vertices":[[-2,-1,-7],[2,-1,-7],[2,2,-7],[-2,2,-7]],"color":[90,90,90]}\n')
    w(f"{t}/tex.json", SCENE)
    w(f"{t}/texuv.json", SCENE +
      '{"rect":[-1,-1,1,1],"color":[9,9,9],"pattern":{"file":"p.pat","incr":0.3,"horz":0.25}}\n'
      '{"object":"tri","records":[{"vertices":[[0,0,0],[1,0,0],[0,1,0]],"pattern":{"file":"p.pat","incr":0.13,"rotate":-20}}]}\n'
      '{"instance":"tri","transform":[{"rotate":30,"axis":"y"},{"translate":[1,-0.5,-3]}]}\n'
      '{"instance":"tri","transform":[{"translate":[-2,0,-6]}]}\n')
    w(f"{t}/aligned.json", '{"vertices":[[3,5],[43,5],[43,37],[3,37]],"color":[1,2,3],"pattern":{"file":"p.pat","incr":2}}')
    quad = lambda m: ('{"vertices":[[0,0],[400,0],[400,300],[0,300]],"uv":[[0,0],[%s,0],[%s,%s],[0,%s]],'
                      '"color":[0,0,0],"pattern":{"file":"q.pat"}}' % (m, m, m, m))
    w(f"{t}/quad2.json", quad("2.0"))
    w(f"{t}/quad20.json", quad("20.0"))
    w(f"{t}/xgl.json", '{"vertices":[[0,0],[64,0],[64,64],[0,64]],"uv":[[-8,-8],[24,-8],[24,24],[-8,24]],"color":[50,60,70],"pattern":{"file":"b.pat"}}')
    w(f"{t}/persp-uv.json", '{"vertices":[[-1,-1,-1],[1,-1,-1],[1,-1,-3],[-1,-1,-3]],"uv":[[0,0],[2,0],[2,2],[0,2]],"color":[0,0,0],"pattern":{"file":"q.pat"}}')
    w(f"{t}/compose.json", '{"vertices":[[0,0],[64,0],[64,64],[0,64]],"uv":[[0,0],[16,0],[16,16],[0,16]],"color":[255,128,0],"pattern":{"file":"w.pat"}}')
    w(f"{t}/uvrecs.json",
      '{"id":1,"vertices":[[1,1],[5,1],[5,3]],"color":[1,2,3],"pattern":{"file":"p.pat","incr":0.5,"horz":1,"vert":-2,"tag":"t"}}\n'
      '{"id":2,"circle":{"center":[0,0],"radius":2},"pattern":{"file":"p.pat","mode":"screen"}}\n'
      '{"id":3,"vertices":[[0,0],[1,0],[0,1]],"color":[4,5,6]}\n')
    w(f"{t}/sliver.json",
      '{"vertices":[[4.108396,-0.08379,-19.600469],[4.897864,0.045591,-19.600469],[4.891604,0.08379,-20.399531],[4.102136,-0.045591,-20.399531]],"color":[128,128,128],"pattern":{"file":"checker.pat","incr":0.1,"rotate":5.53946361142043,"horz":4.168}}\n'
      '{"vertices":[[5.134618,-0.177706,-21.606405],[5.904278,0.040523,-21.606405],[5.865382,0.177706,-22.393595],[5.095722,-0.040523,-22.393595]],"color":[128,128,128],"pattern":{"file":"checker.pat","incr":0.1,"rotate":6.38166442426916,"horz":8.592}}\n')
    w(f"{t}/clampk.json", '{"vertices":[[0,0],[400,0],[400,300],[0,300]],"uv":[[0,0],[160,0],[160,160],[0,160]],"color":[0,0,0],"pattern":{"file":"k.pat"}}')
    w(f"{t}/line.json", '{"vertices":[[200,147.5],[600,447.5],[600,452.5],[200,152.5]],"uv":[[0,0],[16,0],[16,1],[0,1]],"color":[0,0,0],"pattern":{"file":"l.pat"}}')
    w(f"{t}/c48.json", '{"vertices":[[-400,-1,-1],[400,-1,-1],[400,-1,-801],[-400,-1,-801]],"uv":[[0,0],[4800,0],[4800,4800],[0,4800]],"color":[255,0,0],"pattern":{"file":"c48.pat"}}')
    w(f"{t}/skipscene.json",
      '{"vertices": [[-60, 0, -1], [60, 0, -1], [60, 0, -120], [-60, 0, -120]], "color": [90, 90, 90], "pattern": {"file": "dots.pat", "incr": 0.5}}\n'
      '{"vertices": [[-1, 0.2, -9], [1, 0.2, -9], [1, 1.2, -9], [-1, 1.2, -9]], "color": [10, 200, 10], "pattern": {"file": "opaque.pat", "incr": 0.1, "rotate": 20}}\n'
      '{"vertices": [[-3, -1, -6], [3, -1, -6], [3, 2, -5], [-3, 2, -5]], "color": [128, 128, 128], "pattern": {"file": "opaque.pat", "incr": 0.05, "rotate": 7}}\n')
    w(f"{t}/emptyscene.json", "")

    # polyfill3.rs
    w(f"{t}/passthrough.json", '{"id":7,"vertices":[[0,0,0],[1,0,0],[0,1,0]],"color":[1,2,3],"tag":{"x":[1.5]}}\n')
    w(f"{t}/sq.json", '[{"id":"sq","vertices":[[0,0],[2,0],[2,2],[0,2]],"pattern":{"file":"p1hole.pat","incr":1},"uv_note":1}]')
    w(f"{t}/twod.json", '{"rect":[0,0,100,50],"pattern":{}}\n{"circle":{"center":[0,0],"radius":10},"pattern":{"incr":1}}\n')
    w(f"{t}/merge.json", '{"vertices":[[0,0,0],[30,0,0],[30,0,-20],[0,0,-20]],"pattern":{"file":"p1stripes.pat","incr":1.5}}')
    w(f"{t}/under.json", '{"vertices":[[-500,0,-800],[500,0,-800],[500,0,0],[-500,0,0]],"pattern":{"file":"' + os.path.join(ROOT, "fixtures/patterns/chex.pat") + '","incr":25}}')
    w(f"{t}/tri-rect.json", '{"vertices":[[0,0,0],[4,0,0],[0,4,0]],"pattern":{"file":"p1.pat"}}\n{"rect":[0,0,1,1],"color":[1,1,1]}\n')
    ok = '{"vertices":[[0,0],[1,0],[0,1]],"pattern":{"file":"p1.pat"}}'
    bad_cases = [
        '{"vertices":[[0,0],[1,0]],"pattern":{"file":"p1.pat"}}',
        '{"vertices":[[0,0],[1,0],[2,0]],"pattern":{"file":"p1.pat"}}',
        '{"vertices":[[0,0,0],[1,0,0],[1,1,0.5],[0,1,0]],"pattern":{"file":"p1.pat"}}',
        '{"vertices":[[0,0],[1,0],[0,NaN]],"pattern":{"file":"p1.pat"}}',
        '{"vertices":[[0,0],[1,0],[0,1]],"pattern":{"file":"p1.pat","incr":0}}',
        '{"vertices":[[0,0],[1,0],[0,1]],"pattern":{"file":"nope.pat"}}',
        '{"vertices":[[0,0],[1,0],[0,1]],"pattern":{"file":"bad3.pat"}}',
        '{"vertices":[[0,0],[1,0],[0,1]],"pattern":{}}',
        '{"vertices":[[0,0],[1000,0],[0,1000]],"pattern":{"file":"p1.pat","incr":0.01}}',
    ]
    for i, b in enumerate(bad_cases):
        w(f"{t}/p3bad{i}.json", ok + "\n" + b + "\n")
    w(f"{t}/p3ok.json", ok)
    face = ok
    obj_cases = [
        face + '\n{"instance":"ghost"}',
        '{"object":"a","records":[{"instance":"a"}]}',
        '{"object":"a","records":[%s]}\n{"object":"a","records":[]}' % face,
        '{"object":"a","records":[]}\n{"instance":"a","transform":{"scale":[1,0,1]}}',
        '{"object":"a","records":[{"vertices":[[0,0],[1,0],[2,0]],"pattern":{"file":"p1.pat"}}]}',
    ]
    for i, b in enumerate(obj_cases):
        w(f"{t}/objbad{i}.json", b)

    # quadric.rs
    w(f"{t}/sphere40.json", '{"sphere": {"radius": 40}, "transform": {"translate": [100, 100, 0]}, "color": [255,255,255]}')
    w(f"{t}/sphere-hex.json", '{"sphere": {"radius": 40, "slices": 6, "stacks": 40}, "transform": {"translate": [100, 100, 0]}, "color": [255,255,255]}')
    w(f"{t}/seam.json", """{"sphere": {"radius": 40, "slices": 24, "stacks": 12},
            "transform": [{"rotate": 90, "axis": "x"}, {"translate": [100, 100, 0]}],
            "color": [0,255,0], "pattern": {"file": "half.pat"}}""")
    quad_bad = [
        '{"sphere": {"radius": 0}, "color": [1,2,3]}',
        '{"sphere": {"radius": -2}, "color": [1,2,3]}',
        '{"sphere": {"radius": 1, "slices": 2}, "color": [1,2,3]}',
        '{"sphere": {"radius": 1, "stacks": 1}, "color": [1,2,3]}',
        '{"cylinder": {"base": 1, "top": 1, "height": 0}, "color": [1,2,3]}',
        '{"cone": {"base": -1, "height": 2}, "color": [1,2,3]}',
        '{"disk": {"inner": 3, "outer": 2}, "color": [1,2,3]}',
        '{"disk": {"outer": 2, "stacks": 3}, "color": [1,2,3]}',
        '{"sphere": {"radius": "big"}, "color": [1,2,3]}',
        '{"sphere": {"radius": 1e999}, "color": [1,2,3]}',
        '{"sphere": {"radius": 1}, "pattern": {"file": "p.pat", "mode": "object"}}',
        '{"sphere": {"radius": 1}, "transform": {"scale": 0}, "color": [1,2,3]}',
    ]
    for i, b in enumerate(quad_bad):
        w(f"{t}/qbad{i}.json", '{"rect": [0,0,1,1], "color": [0,0,0]}\n' + b + "\n")
    w(f"{t}/ball.json",
      '{"object": "ball", "records": [{"sphere": {"radius": 30, "slices": 8, "stacks": 4}, "color": [0,255,0], "pattern": {"file": "half.pat"}, "id": "b"}]}\n'
      '{"instance": "ball", "transform": {"translate": [60, 100, 0]}}\n'
      '{"cylinder": {"base": 20, "top": 10, "height": 40, "slices": 12, "stacks": 2}, "transform": [{"rotate": -60, "axis": "x"}, {"translate": [150, 100, 0]}], "color": [200,200,0]}\n')
    w(f"{t}/qspin.json", '{"sphere":{"radius":1},"transform":{"rotate":{"start":0,"step":5},"axis":"z"},"color":[1,2,3]}')
    w(f"{t}/qdirect.json", '{"sphere": {"radius": 20}, "transform": [{"rotate": 30, "axis": "y"}, {"translate": [100, 100, 0]}], "color": [255,128,0]}')
    w(f"{t}/qplaced.json", '{"object": "o", "records": [{"sphere": {"radius": 20}, "transform": {"rotate": 30, "axis": "y"}, "color": [255,128,0]}]}\n'
                           '{"instance": "o", "transform": {"translate": [100, 100, 0]}}')
    w(os.path.join(d("docs"), "quadrics.json"),  # docs/objects.md quadric records
      '{"sphere": {"radius": 40, "slices": 80, "stacks": 80}, "transform": [{"rotate": -90, "axis": "x"}, {"translate": [-30, 0, -50]}], "color": [255, 255, 255], "pattern": {"file": "' + os.path.join(ROOT, "fixtures/patterns/earth.pat") + '", "mode": "uv"}}\n'
      '{"cylinder": {"base": 10, "top": 5, "height": 30, "slices": 32, "stacks": 4}, "color": [200, 0, 0]}\n'
      '{"cone": {"base": 10, "height": 30}, "transform": {"translate": [40, 20, -20]}, "color": [0, 200, 0]}\n'
      '{"disk": {"inner": 2, "outer": 10, "slices": 32, "loops": 2}, "transform": {"translate": [50, -30, -10]}, "color": [0, 0, 200]}\n')

    # stripe.rs
    def stripe_scene(name, ground_stripe):
        ground = {"vertices": [[-50, 0, 0], [50, 0, 0], [50, 0, -100], [-50, 0, -100]],
                  "color": [100, 150, 60], "id": "ground", "stripe": ground_stripe}
        wall = {"vertices": [[-10, 0, -50], [10, 0, -50], [10, 10, -50], [-10, 10, -50]],
                "color": [200, 200, 200],
                "stripe": {"map": "maps/m.map", "spacing": 0.25, "plane": "yz", "theta": 30,
                           "translation": "maps/s.tm", "select": "rb"}}
        w(f"{t}/{name}", json.dumps(ground) + "\n" + json.dumps(wall) + "\n")

    stripe_scene("sscene.json", {"map": "maps/m.map", "spacing": 2, "phase": 3, "yaw": 90, "pitch": 0, "code": 4})
    for i, g in enumerate([
        {"map": "maps/m.map", "spacing": 0, "yaw": 0},
        {"map": "maps/m.map", "spacing": -1, "yaw": 0},
        {"map": "maps/m.map", "spacing": 1, "yaw": 361},
        {"map": "maps/m.map", "spacing": 1, "yaw": 0, "pitch": 95},
        {"map": "maps/none.map", "spacing": 1, "yaw": 0},
        {"map": "maps/m.map", "spacing": 1, "yaw": 0, "translation": "maps/short.tm"},
        {"map": "maps/odd.map", "spacing": 1, "yaw": 0},
    ]):
        stripe_scene(f"sbad{i}.json", g)
    stripe_scene("sscene2.json", {"map": "maps/m.map", "spacing": 1, "yaw": 0})
    w(f"{t}/splain.json", '{"vertices": [[0,0],[1,0],[0,1]], "color": [1,2,3]}\n')
    png(f"{t}/bars.png", 8, 4, lambda x, y: (0, 0, 0, 255) if x % 2 == 0 else (255, 255, 255, 255))
    w(f"{t}/flatwall.json", '{"vertices": [[0,0],[999,0],[999,8],[0,8]], "stripe": {"map": "m.map", "spacing": 0.37, "yaw": 0}}')
    w(f"{t}/spersp.json",
      '{"vertices": [[-200,0,0],[200,0,0],[200,0,-2000],[-200,0,-2000]], "color": [180,170,150], "stripe": {"map": "runway.map", "spacing": 0.05, "yaw": 90}}\n'
      '{"vertices": [[-20,0,-60],[20,0,-60],[20,25,-60],[-20,25,-60]], "stripe": {"map": "m.map", "spacing": 0.5, "yaw": 30, "pitch": 20, "code": 172, "select": "rg"}}\n')
    for i, st in enumerate([
        '{"map": "m.map", "spacing": 0, "yaw": 0}',
        '{"map": "m.map", "spacing": -0.5, "yaw": 0}',
        '{"map": "m.map", "spacing": 1, "yaw": 400}',
        '{"map": "m.map", "spacing": 1, "yaw": 0, "pitch": -95}',
        '{"map": "m.map", "spacing": 1, "yaw": 0, "select": "rq"}',
        '{"map": "m.map", "spaceing": 1, "yaw": 0}',
        '{"map": "missing.map", "spacing": 1, "yaw": 0}',
        '{"map": "odd.map", "spacing": 1, "yaw": 0}',
        '{"map": "m.map", "spacing": 1, "yaw": 0, "translation": "short.tm"}',
    ]):
        w(f"{t}/srbad{i}.json", '{"vertices": [[0,0],[9,0],[9,9]], "color": [1,2,3]}\n{"vertices": [[0,0],[9,0],[9,9]], "stripe": %s}\n' % st)
    w(f"{t}/both.json", '{"vertices": [[0,0],[9,0],[9,9]], "pattern": {"file": "c.pat"}, "stripe": {"map": "m.map", "spacing": 1, "yaw": 0}}')
    stripe = '"stripe": {"map": "m.map", "spacing": 0.7, "yaw": 0, "phase": 1.5}'
    w(f"{t}/sinst.json", '{"object": "w", "records": [{"vertices": [[3,2],[50,2],[50,20],[3,20]], %s}]}\n'
                         '{"instance": "w", "transform": [{"translate": [0, 11, 0]}]}\n' % stripe)
    w(f"{t}/sflat.json", '{"vertices": [[3,13],[50,13],[50,31],[3,31]], %s}\n' % stripe)

    # stress.rs
    def sscene(tr, s):
        polys = [
            ([[-1.0, -1.0, -5.0], [1.2, -1.0, -5.0], [1.0, 1.0, -5.0], [-1.0, 1.3, -5.0]],
             '"pattern":{"file":"brick.pat","incr":0.0625}'),
            ([[-2.0, -0.5, -7.0], [2.0, -0.3, -4.0], [0.0, 2.0, -6.0]],
             '"pattern":{"file":"brick.pat","incr":0.05,"rotate":30,"horz":0.5}'),
            ([[-3.0, -2.0, -9.0], [3.0, -2.0, -9.0], [0.0, 2.5, -9.5]], '"color":[40,90,200]'),
        ]
        out = ""
        for v, rest in polys:
            vs = ",".join("[%r,%r,%r]" % (p[0] * s + tr, p[1] * s + tr, p[2] * s + tr) for p in v)
            rest = rest.replace("0.0625", repr(0.0625 * s)).replace("0.05,", "%r," % (0.05 * s))
            out += '{"vertices":[%s],"color":[200,30,30],%s}\n' % (vs, rest)
        return out

    w(f"{t}/st-t0.json", sscene(0.0, 1.0))
    w(f"{t}/st-t1e7.json", sscene(1e7, 1.0))
    for e in (-6, -3, 3, 6, 9):
        w(f"{t}/st-s1e{e}.json", sscene(0.0, 10.0 ** e))
    for rep in (0, 1e3, 1e7):
        o = 64.0 * rep
        w(f"{t}/st-uv{int(rep)}.json",
          '{"vertices":[[0,0],[64,0],[64,48],[0,48]],"uv":[[%r,%r],[%r,%r],[%r,%r],[%r,%r]],"color":[0,0,0],"pattern":{"file":"brick.pat","mode":"uv"}}'
          % (o + 0.3, o + 0.1, o + 13.7, o + 2.2, o + 15.1, o + 11.9, o + 1.1, o + 9.8))
    w(f"{t}/st-floor.json", '{"vertices":[[-5,-1,5],[5,-1,5],[5,-1,-50],[-5,-1,-50]],"color":[200,30,30],"pattern":{"file":"brick.pat","incr":0.25}}')
    w(f"{t}/st-floorflat.json", '{"vertices":[[-5,-1,5],[5,-1,5],[5,-1,-50],[-5,-1,-50]],"color":[200,30,30]}')
    for e in (-6, -2, 0, 6):
        w(f"{t}/st-incr1e{e}.json", '{"vertices":[[0,0,0],[1,0,0],[1,1,0],[0,1,0]],"color":[1,2,3],"pattern":{"file":"brick.pat","incr":%r}}' % (10.0 ** e))
    for i, incr in enumerate(["1e-20", "5e-324"]):
        w(f"{t}/st-fine{i}.json", '{"rect":[0,0,1,1],"color":[0,0,0]}\n{"vertices":[[0,0,0],[1,0,0],[1,1,0],[0,1,0]],"color":[1,2,3],"pattern":{"file":"brick.pat","incr":%s}}' % incr)
    for i, (key, value) in enumerate([("horz", "1e17"), ("vert", "-1e19"), ("horz", "1e9"), ("horz", "0")]):
        w(f"{t}/st-shift{i}.json", '{"vertices":[[0,0,0],[1,0,0],[1,1,0],[0,1,0]],"color":[1,2,3],"pattern":{"file":"brick.pat","incr":0.25,"%s":%s}}' % (key, value))
    for size in (16, 64, 256, 1024):
        uv = min(64.0, size)
        w(f"{t}/st-p{size}.json", '{"vertices":[[0,0],[64,0],[64,64],[0,64]],"uv":[[0,0],[%r,0],[%r,%r],[0,%r]],"color":[0,0,0],"pattern":{"file":"pt%d.pat","mode":"uv"}}' % (uv, uv, uv, uv, size))
    okr = '{"rect":[0,0,1,1],"color":[0,0,0]}'
    badj = [
        '{"vertices":[[NaN,0],[1,0],[0,1]],"color":[0,0,0]}',
        '{"vertices":[[0,0],[1,0],[0,Infinity]],"color":[0,0,0]}',
        '{"vertices":[[0,0],[1,0],[0,-1e400]],"color":[0,0,0]}',
        '{"vertices":[[0,0],[1,0],[0,1]],"color":[0,0,0],"pattern":{"incr":1e999}}',
        '{"x":%s1%s}' % ("[" * 100000, "]" * 100000),
        '{"vertices":[[0,0],[1,0],[0,1]],"col',
        '{"vertices":[[0,0],[1,0],[0,1]],"color":[0,0,0]',
    ]
    for i, b in enumerate(badj):
        w(f"{t}/st-json{i}.json", okr + "\n" + b)
    for i, rec in enumerate([
        '{"vertices":[[-1e15,-1e15],[1e15,-1e15],[0,1e15]],"color":[255,255,255]}',
        '{"vertices":[[-1e9,-1e9],[1e9,-1e9],[0,1e9]],"color":[255,255,255]}',
        '{"circle":{"center":[8,8],"radius":1e12},"color":[255,255,255]}',
        '{"vertices":[[0,0],[1e308,0],[0,1e308]],"color":[0,0,0],"pattern":{"file":"brick.pat"}}',
    ]):
        w(f"{t}/st-huge{i}.json", rec)

    def star(n, radii):
        pts = []
        for i in range(n):
            a = math.tau * i / n
            r = radii[i % 2]
            pts.append("[%r,%r]" % (8.0 + r * math.cos(a), 8.0 + r * math.sin(a)))
        return '{"vertices":[' + ",".join(pts) + '],"color":[255,255,255]}'

    w(f"{t}/st-star20002.json", star(20002, [7.0, 5.0]))
    w(f"{t}/st-star2000.json", star(2000, [7.0, 5.0]))
    w(f"{t}/st-disc20000.json", star(20000, [7.0, 7.0]))
    w(f"{t}/st-circle.json", '{"circle":{"center":[8,8],"radius":7},"color":[255,255,255]}')

    # pat_from_image.rs images
    def sample(x, y):
        if x == 5:
            return (77, 77, 77, 0)
        if y == 0:
            return (255, 0, 0, 255)
        if y == 31:
            return (0, 0, 255, 255)
        if (x, y) == (3, 10):
            return (255, 255, 255, 255)
        return (0, 160, 0, 255)

    png(f"{t}/in.png", 32, 32, sample)
    png(f"{t}/wide.png", 48, 32, lambda x, y: ((x * 8) % 256, (y * 8) % 256, 0, 255)
        if 16 <= x < 32 and 8 <= y < 24 else (0, 0, 0, 255))
    png(f"{t}/grad.png", 100, 70, lambda x, y: ((x * 2) % 256, (y * 3) % 256, 128, 255))
    w(f"{t}/junk.png", "this is not an image")
    w(f"{t}/pal.txt", "# two colours\n#000000\n250,250,250 # light\n")
    w(f"{t}/badpal.txt", "1,2,3\n#12345\n")
    w(f"{t}/ega.txt", "#000000\n#0000aa\n#00aa00\n#00aaaa\n#aa0000\n#aa00aa\n#aa5500\n#aaaaaa\n"
      "#555555\n#5555ff\n#55ff55\n#55ffff\n#ff5555\n#ff55ff\n#ffff55\n#ffffff\n")
    png(f"{t}/icon.png", 40, 40, lambda x, y: (255, 0, 255, 255) if (x + y) % 7 == 0
        else ((x * 6) % 256, (y * 6) % 256, ((x ^ y) * 4) % 256, 255))


def bench_images():
    """Stand-ins for bench/pat_from_image.sh's ImageMagick images (not available)."""
    b = d("img")
    for n in (64, 256):
        png(f"{b}/gradient-{n}.png", n, n, lambda x, y: (  # navy to gold
            round(255 * y / (n - 1)), round(215 * y / (n - 1)), round(128 - 128 * y / (n - 1)), 255))
        png(f"{b}/radial-{n}.png", n, n, lambda x, y: (
            round(255 - (255 - 139) * min(1.0, math.hypot(x - n / 2, y - n / 2) / (n / 2))),
            round(255 - 255 * min(1.0, math.hypot(x - n / 2, y - n / 2) / (n / 2))),
            round(255 - 255 * min(1.0, math.hypot(x - n / 2, y - n / 2) / (n / 2))), 255))
        png(f"{b}/plasma-{n}.png", n, n, lambda x, y: (
            int(127.5 + 127.5 * math.sin(x * 12.0 / n + math.sin(y * 7.0 / n))),
            int(127.5 + 127.5 * math.sin(y * 9.0 / n + 2 * math.cos(x * 5.0 / n))),
            int(127.5 + 127.5 * math.cos((x + y) * 6.0 / n)), 255))

        def drawing(x, y, n=n):
            s = 256.0 / n
            X, Y = x * s, y * s
            c = (round(135 + 120 * Y / 256), round(206 + 49 * Y / 256), round(235 + 20 * Y / 256))
            if abs((X + Y) - 250) < 3.5:
                c = (0, 0, 0)
            if 140 <= X <= 240 and 120 <= Y <= 230:
                c = (46, 139, 87)
            if math.hypot(X - 90, Y - 90) <= 60:
                c = (255, 99, 71)
            if ((X - 70) / 50) ** 2 + ((Y - 190) / 30) ** 2 <= 1:
                c = (255, 215, 0)
            return c + (255,)

        png(f"{b}/drawing-{n}.png", n, n, drawing)
        rnd = random.Random(7)
        noise = [[rnd.randrange(256) for _ in range(3 * n)] for _ in range(n)]
        png(f"{b}/noise-{n}.png", n, n, lambda x, y: (noise[y][3 * x], noise[y][3 * x + 1], noise[y][3 * x + 2], 255))
        png(f"{b}/alpha-{n}.png", n, n, lambda x, y: ((x * 255) // (n - 1), (y * 255) // (n - 1), 90,
                                                     (x * 255) // (n - 1)))


def docs():
    """README, docs/*.md and --help examples that need files."""
    o = d("docs")
    fx = os.path.join(ROOT, "fixtures")
    # README scene-render 2D example: shapes.json
    w(f"{o}/shapes.json", jl([
        {"rect": [20, 20, 300, 200], "color": [200, 40, 40]},
        {"circle": {"center": [500, 400], "radius": 150}, "color": [40, 160, 40]},
        {"arc": {"center": [800, 300], "radius": 120, "start": 10, "end": 250}, "color": [40, 40, 200]},
        {"vertices": [[100, 600], [400, 700], [300, 450]], "color": [220, 200, 30]},
        {"rect": [600, 550, 1000, 750], "pattern": {"file": f"{fx}/patterns/weave.pat", "mode": "screen"}},
    ]))
    # README polyfill3: faces.json whose patterns leave out the file (and incr/horz)
    faces = [json.loads(l) for l in open(f"{fx}/scenes/demo2-faces.json")]
    for f in faces:
        f["pattern"] = {}
    w(f"{o}/faces.json", jl(faces))
    w(f"{o}/cam.json", json.dumps({"lookat": {"eye": [0, 100, -5], "center": [0, 0, -900], "twist": 0},
                                   "perspective": {"fovy": 55, "aspect": 1.0, "near": 0, "far": 1000}}) + "\n")
    w(f"{o}/demo2.camera.json", open(f"{o}/cam.json").read())
    # docs/camera.md: the textbook camera JSON and the equivalent IRIS camera
    w(f"{o}/textbook-cam.json", json.dumps({"view": {"vrp": [0, 0, 0], "vpn": [0, 0, -1], "view_up": [0, 1, 0],
                                                     "view_distance": 0, "window": [-1, 1, -1, 1],
                                                     "cop": [0, 0, 2], "front": 0, "back": 10}}) + "\n")
    w(f"{o}/cube.json", jl([  # a small scene for the textbook / oblique cameras
        {"vertices": [[-0.5, -0.5, -1], [0.5, -0.5, -1], [0.5, 0.5, -1], [-0.5, 0.5, -1]], "color": [200, 60, 60]},
        {"vertices": [[0.5, -0.5, -1], [0.5, -0.5, -2], [0.5, 0.5, -2], [0.5, 0.5, -1]], "color": [60, 200, 60]},
        {"vertices": [[-0.5, 0.5, -1], [0.5, 0.5, -1], [0.5, 0.5, -2], [-0.5, 0.5, -2]], "color": [60, 60, 200]},
        {"vertices": [[-3, -1, -0.5], [3, -1, -0.5], [3, -1, -6], [-3, -1, -6]], "color": [128, 128, 128],
         "pattern": {"file": f"{fx}/patterns/chex.pat", "incr": 0.25}},
    ]))
    # docs/objects.md: face object and instance (pyr.pat beside the stream)
    shutil.copy(f"{fx}/patterns/pyr.pat", f"{o}/pyr.pat")
    shutil.copy(f"{fx}/patterns/earth.pat", f"{o}/earth.pat")
    w(f"{o}/face-instance.json",
      '{"object": "face", "records": [{"vertices": [[100,0,100],[100,0,-100],[0,142.2,0]],\n'
      '                                "color": [160,82,45], "pattern": {"file": "pyr.pat", "incr": 2, "horz": -5}}]}\n'
      '{"instance": "face", "transform": [{"rotate": 90, "axis": "y"}, {"translate": [0, 0, -500]}]}\n')
    w(f"{o}/readme-face.json",
      '{"object": "face", "records": [{"vertices": [[100,0,100],[100,0,-100],[0,142.2,0]], "pattern": {"incr": 2}}]}\n'
      '{"instance": "face", "transform": [{"rotate": 90, "axis": "y"}, {"translate": [0, 0, -500]}]}\n')
    w(f"{o}/readme-sphere.json",
      '{"sphere": {"radius": 40, "slices": 80, "stacks": 80}, "transform": [{"rotate": -90, "axis": "x"}, {"translate": [-30, 0, -50]}],\n'
      ' "color": [255, 255, 255], "pattern": {"file": "earth.pat", "mode": "uv"}}\n')
    w(f"{o}/transforms.json", jl([  # every transform step of the docs/objects.md table
        {"object": "sq", "records": [{"vertices": [[0, 0, 0], [10, 0, 0], [10, 10, 0], [0, 10, 0]], "color": [250, 250, 250],
                                      "pattern": {"file": "pyr.pat", "incr": 0.5}}]},
        {"instance": "sq", "transform": {"translate": [10, 10, 0]}},
        {"instance": "sq", "transform": [{"scale": 0.5}, {"translate": [40, 10, 0]}]},
        {"instance": "sq", "transform": [{"scale": [1, 1.5, 1], "about": [5, 5, 0]}, {"translate": [70, 10, 0]}]},
        {"instance": "sq", "transform": [{"rotate": 30, "axis": "z"}, {"translate": [20, 40, 0]}]},
        {"instance": "sq", "transform": [{"rotate": 45, "axis": [1, 1, 1], "point": [5, 5, 0]}, {"translate": [50, 40, 0]}]},
        {"instance": "sq", "transform": {"matrix": [[1, 0, 0, 0], [0.3, 1, 0, 0], [0, 0, 1, 0], [80, 40, 0, 1]]}},
        {"object": "nest", "records": [{"instance": "sq", "transform": {"scale": 0.3}},
                                       {"instance": "sq", "transform": [{"scale": 0.3}, {"translate": [4, 0, 0]}]}]},
        {"instance": "nest", "transform": [{"rotate": {"start": 0, "step": 15}, "axis": "z"}, {"translate": [10, 70, 0]}]},
    ]))
    # docs/stripe.md: field.json (maps beside it) and the schema example
    for m in ("runway.map", "furrow.map", "crops.map", "s-curve.tm", "terrain.ct"):
        shutil.copy(f"{fx}/stripes/{m}", f"{o}/{m}")
    w(f"{o}/field.json",
      '{"vertices": [[-200,0,0],[200,0,0],[200,0,-2000],[-200,0,-2000]], "color": [180,170,150],\n'
      ' "stripe": {"map": "runway.map", "spacing": 0.05, "yaw": 90}}\n'
      '{"vertices": [[-20,0,-60],[20,0,-60],[20,25,-60],[-20,25,-60]],\n'
      ' "stripe": {"map": "furrow.map", "spacing": 0.04, "yaw": 30, "pitch": 20, "code": 172, "select": "rg"}}\n')
    w(f"{o}/stripe-schema.json", jl([
        {"vertices": [[-50, 0, 0], [50, 0, 0], [50, 0, -100], [-50, 0, -100]], "color": [100, 150, 60],
         "stripe": {"map": "furrow.map", "spacing": 0.25, "phase": 0, "yaw": 90, "pitch": 0,
                    "translation": {"contrast": 1.5}, "select": "rgb", "code": 20}},
        {"vertices": [[-10, 0, -40], [10, 0, -40], [10, 8, -40], [-10, 8, -40]], "color": [90, 90, 200],
         "stripe": {"map": "crops.map", "spacing": 0.02, "plane": "xy", "theta": 15,
                    "translation": "s-curve.tm", "colors": "terrain.ct", "code": 3}},
        {"vertices": [[12, 0, -45], [12, 0, -35], [12, 8, -35], [12, 8, -45]], "color": [200, 90, 90],
         "stripe": {"map": "runway.map", "spacing": 0.05, "plane": "yz", "theta": -40,
                    "translation": {"brightness": -30}, "select": "g"}},
        {"vertices": [[-30, 0, -20], [-12, 0, -20], [-12, 0, -60], [-30, 0, -60]],
         "stripe": {"map": "crops.map", "spacing": 0.1, "plane": "zx", "theta": 30, "translation": "identity"}},
    ]))
    w(f"{o}/stripe-edit.json", jl([  # the jq editing example, done in Python
        {"id": "field", "vertices": [[-50, 0, 0], [50, 0, 0], [50, 0, -100], [-50, 0, -100]], "color": [100, 150, 60],
         "stripe": {"map": "furrow.map", "spacing": 0.5, "yaw": 90}}]))
    png(f"{o}/field.png", 64, 48, lambda x, y: (int(128 + 100 * math.sin(y / 3.0)),) * 3 + (255,))


def bench(bindir_unused=None):
    # bench/texbench.py (texture.sh, tradeoff.sh): imported
    import texbench
    tb = d("texbench")
    texbench.scenes(tb, ["plane", "wall", "demo2", "demo1", "tiles"])
    for name, scene in [("plane", f"{tb}/plane.json"), ("wall", f"{tb}/wall.json"), ("tiles", f"{tb}/tiles.json"),
                        ("demo2", os.path.join(ROOT, "examples/scenes/demo2.json")),
                        ("demo1", os.path.join(ROOT, "examples/scenes/demo1.json"))]:
        for factor in (4.0, 2.0, 1.0, 0.5):
            texbench.scaled(scene, factor, f"{tb}/{name}-x{factor}.json")

    # bench/skips.py (skips.sh): imported, the 200-file directory kept
    import skips
    sk = d("skips")
    skips.scenes(sk)
    skips.referenced_scenes(sk)

    # bench/stripe.sh: its heredoc's scene part, executed as is
    st = d("stripe")
    shutil.copy(os.path.join(ROOT, "fixtures/stripes/runway.map"), f"{st}/runway.map")
    src = open(os.path.join(ROOT, "bench/stripe.sh")).read()
    code = src.split("<<'PY'\n", 1)[1].split("\nPY\n", 1)[0].split("\nview = [", 1)[0]
    saved = sys.argv
    sys.argv = ["stripe.sh", "scene-render", st, "1"]
    exec(compile(code, "bench/stripe.sh", "exec"), {"__name__": "stripe_sh"})
    sys.argv = saved

    # The scenes of the former bench/max_error.sh (--max-error was removed;
    # run.sh still runs them every way), minus the polyfill3 call (run.sh runs it)
    me = d("maxerr")
    text = open(os.path.join(ROOT, "examples/scenes/demo2.json")).read()
    with open(f"{me}/demo2.json", "w") as fh:
        fh.write(text.replace('"../../fixtures/', '"%s/fixtures/' % ROOT))
    with open(f"{me}/checker.pat", "w") as fh:
        fh.write("16 2\n230 230 230\n" + "".join(
            "%04x\n" % (0xAAAA if r % 2 == 0 else 0x5555) for r in range(16)) + "20 20 120\n" + "".join(
            "%04x\n" % (0x5555 if r % 2 == 0 else 0xAAAA) for r in range(16)))
    with open(f"{me}/plane.json", "w") as fh:
        fh.write(json.dumps(
            {"vertices": [[-200, 0, -1], [200, 0, -1], [200, 0, -401], [-200, 0, -401]],
             "color": [128, 128, 128], "pattern": {"file": "checker.pat", "incr": 1}}) + "\n")
    with open(f"{me}/fan.json", "w") as fh:
        for i in range(240):
            a0, a1 = (i / 240) * 2 * math.pi, ((i + 0.5) / 240) * 2 * math.pi
            c = [250, 40, 40] if i % 2 == 0 else [20, 200, 90]
            fh.write(json.dumps({"vertices": [[512, 384], [512 + 370 * math.cos(a0), 384 + 370 * math.sin(a0)],
                                              [512 + 370 * math.cos(a1), 384 + 370 * math.sin(a1)]], "color": c}) + "\n")

    # bench/demo2_scene.py (scene_render.sh's stand-in partitioner): run as is
    sr = d("scenerender")
    for incr in ("2", "1"):
        with open(f"{sr}/demo2-py-incr{incr}.ndjson", "w") as fh:
            subprocess.run([sys.executable, os.path.join(ROOT, "bench/demo2_scene.py"),
                            os.path.join(ROOT, "fixtures/patterns"), incr], stdout=fh, check=True, cwd=ROOT)
    # bench/scene_render.sh: demo2.json with the pyramid's incr set (its sed), paths made absolute
    text = open(os.path.join(ROOT, "examples/scenes/demo2.json")).read()
    for incr in ("2", "1"):
        t = text.replace('"incr": 2,', '"incr": %s,' % incr).replace('"../../fixtures/', '"%s/fixtures/' % ROOT)
        w(f"{sr}/demo2-incr{incr}.json", t)
    # scene_render_bench.py --random-triangles needs numpy (absent): the same
    # distribution with Python's random, REDUCED from 1,000,000 to 100,000.
    rnd = random.Random(1)
    W, H = 1024, 768
    with open(f"{sr}/triangles-100k.ndjson", "w") as fh:
        for i in range(100000):
            cx, cy = rnd.random() * W, rnd.random() * H
            a = [rnd.random() * 2 * math.pi for _ in range(3)]
            r = 3.5 + rnd.random() * 1.0
            z = rnd.random() * 1.8 - 0.9
            col = [rnd.randrange(256) for _ in range(3)]
            v = [[round(cx + r * math.cos(a[k]), 3), round(cy + r * math.sin(a[k]), 3), round(z, 4)] for k in range(3)]
            fh.write(json.dumps({"vertices": v, "color": col}, separators=(",", ":")) + "\n")

    # bench/animate.sh: its sed edits of demo2-spin, demo2 and demo2-fig51 (incr 2 and 1)
    an = d("animate")
    spin = open(os.path.join(ROOT, "fixtures/scenes/demo2-spin.json")).read()
    fig = open(os.path.join(ROOT, "fixtures/scenes/demo2-fig51.json")).read()
    for incr in ("2", "1"):
        w(f"{an}/spin-incr{incr}.json", spin.replace('"incr":2,', '"incr":%s,' % incr)
          .replace("../patterns/", "%s/fixtures/patterns/" % ROOT))
        w(f"{an}/four-incr{incr}.json", text.replace('"incr": 2,', '"incr": %s,' % incr)
          .replace("../../fixtures/patterns/", "%s/fixtures/patterns/" % ROOT))
        w(f"{an}/fig51-incr{incr}.json", fig.replace('"incr":2,', '"incr":%s,' % incr)
          .replace("../patterns/", "%s/fixtures/patterns/" % ROOT))


if __name__ == "__main__":
    os.makedirs(SC, exist_ok=True)
    tests()
    bench_images()
    docs()
    bench()
