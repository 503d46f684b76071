#!/usr/bin/env python3
"""Driver of bench/texture.sh and bench/tradeoff.sh: textured scenes rendered
by every method of the toolchain and by llvmpipe (bench/llvmpipe_texture.py),
each timed and measured against `scene-render --reference`.

    texbench.py texture  BIN_DIR WORK [SCENE...]  # per-scene tables with the issue's goals
    texbench.py tradeoff BIN_DIR WORK PNG    # one table and the time-against-error plot

Not a test: times depend on the machine and its load. Every run of a method is
a fresh process (or pipeline) timed from outside: the "whole process" time
(start, read, render, write the PNG). "Render only" is what the tool reports
for its own rendering: scene-render's --timings render phase (projection to
pixels, without reading the stream or writing the PNG), llvmpipe's texture and
vertex upload, draw, MSAA resolve and read back.

Methods are the METHODS list below: to add one (say a new `--filter`),
append a dict; "kind" "direct" runs scene-render on the scene with the
extra "args".
"""
import json
import math
import os
import re
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
from timing import medians, run_logged  # noqa: E402

ROOT = os.path.dirname(HERE)

# The methods, in table order. kind:
#   direct   scene-render SCENE + args                  (args: extra flags)
#   p3       polyfill3 (every pattern's incr x factor) | scene-render --aa exact
#   llvmpipe polyfill3 --uv once, then bench/llvmpipe_texture.py per run
# Filters of `scene-render --filter` are appended at run time when the binary
# has the flag (see filter_methods).
METHODS = [
    {"name": "direct --aa exact (default)", "kind": "direct", "args": ["--aa", "exact"], "default": True},
    {"name": "direct --aa ss16", "kind": "direct", "args": ["--aa", "ss16"]},
    {"name": "direct --aa ss4", "kind": "direct", "args": ["--aa", "ss4"]},
    {"name": "direct --aa none", "kind": "direct", "args": ["--aa", "none"]},
    {"name": "polyfill3 incr x4 | exact", "kind": "p3", "factor": 4.0},
    {"name": "polyfill3 incr x2 | exact", "kind": "p3", "factor": 2.0},
    {"name": "polyfill3 incr x1 | exact", "kind": "p3", "factor": 1.0},
    {"name": "polyfill3 incr x0.5 | exact", "kind": "p3", "factor": 0.5},
] + [
    {"name": f"llvmpipe {f}{' MSAA 4x' if m else ''}", "kind": "llvmpipe", "filter": f, "msaa": m}
    for f in ("nearest", "trilinear", "aniso16") for m in (0, 4)
]

# A method whose warm-up run takes longer than this (seconds, whole process) is
# run SLOW_RUNS times instead of the report's usual count, so that the study
# stays within its 10-minute budget (polyfill3 at incr x0.5 on the plane
# writes 640 000 polygons); such rows are marked in the table.
SLOW_RUN_S = 4.0
SLOW_RUNS = 3

# Methods of the texture report (issue 7's columns): no incr sweep there.
TEXTURE_METHODS = [
    m for m in METHODS
    if (m["kind"] != "p3" or m["factor"] == 1.0) and not m.get("tradeoff_only")
]

# RMSE 0 cannot be drawn on a log axis: such points are drawn at this floor
# (8-bit sRGB units; well below one code on one pixel of a 640x480 image,
# sqrt(1 / (3 * 307200)) ~ 1e-3) and the plot says so.
RMSE_FLOOR = 1e-4


def write_checker(work):
    """A 16x16 two-colour checker of single texels (as texture.sh had it)."""
    s = "16 2\n230 230 230\n"
    even = "".join("%04x\n" % (0xAAAA if r % 2 == 0 else 0x5555) for r in range(16))
    odd = "".join("%04x\n" % (0x5555 if r % 2 == 0 else 0xAAAA) for r in range(16))
    s += even + "20 20 120\n" + odd
    with open(os.path.join(work, "checker.pat"), "w") as fh:
        fh.write(s)


# The photograph of the image-texture rows (issue 19): NASA's Blue Marble
# (fixtures/images/ATTRIBUTION.md), resampled to PHOTO_SIDE^2 so that llvmpipe
# gets the same square, power-of-two texture (and polyfill3 --uv a stand-in
# .pat of the same side for its texel coordinates).
PHOTO_SIDE = 1024
PHOTO_SOURCE = os.path.join(ROOT, "fixtures", "images", "earth-nasa.jpg")


def write_photo(work):
    """photo.png (PHOTO_SIDE^2 RGB, lossless so both renderers read the same
    texels) and standin.pat (two colours, the same side) for the uv stream."""
    from PIL import Image
    Image.open(PHOTO_SOURCE).convert("RGB").resize((PHOTO_SIDE, PHOTO_SIDE), Image.LANCZOS).save(
        os.path.join(work, "photo.png"))
    # A .pat row is PHOTO_SIDE / 16 words of four hex digits.
    row = " ".join(["0000"] * (PHOTO_SIDE // 16)) + "\n"
    full = " ".join(["ffff"] * (PHOTO_SIDE // 16)) + "\n"
    with open(os.path.join(work, "standin.pat"), "w") as fh:
        fh.write(f"{PHOTO_SIDE} 2\n0 0 0\n" + row * PHOTO_SIDE + "255 255 255\n" + full * PHOTO_SIDE)


def with_standin(records):
    """The records with photo.png replaced by standin.pat: what polyfill3 --uv
    (which cuts .pat files only) reads to give llvmpipe its uv stream."""
    out = []
    for r in records:
        p = r.get("pattern")
        if p and p.get("file") == "photo.png":
            r = dict(r, pattern=dict(p, file="standin.pat"))
        out.append(r)
    return out


def write_json(path, records):
    with open(path, "w") as fh:
        for r in records:
            fh.write(json.dumps(r) + "\n")


def tiles(rng_seed=5, nx=16, nz=24):
    """Our own scene: a floor of nx x nz (384) small checker tiles (0.8 units on a
    1-unit grid, 8 texels a side), each with its own texture rotation and
    shift and tilted up to 25 degrees about x and z, seen from 1.2 units
    above: many small polygons, most at grazing angles, minified from about
    one texel per pixel in front to dozens far off. The gaps keep tilted
    tiles from touching their neighbours."""
    import random
    rnd = random.Random(rng_seed)
    recs = []
    for i in range(nx):
        for k in range(nz):
            cx, cz = i - nx / 2 + 0.5, -2.0 - k
            ax, az = math.radians(rnd.uniform(-25, 25)), math.radians(rnd.uniform(-25, 25))
            pts = []
            for dx, dz in ((-0.4, 0.4), (0.4, 0.4), (0.4, -0.4), (-0.4, -0.4)):
                # Tilt: rotate the offset about x (dz lifts) then about z.
                y = dz * math.sin(ax)
                z = dz * math.cos(ax)
                x, y = dx * math.cos(az) - y * math.sin(az), dx * math.sin(az) + y * math.cos(az)
                pts.append([round(cx + x, 6), round(y, 6), round(cz + z, 6)])
            recs.append({"vertices": pts, "color": [128, 128, 128],
                         "pattern": {"file": "checker.pat", "incr": 0.1, "rotate": rnd.uniform(0, 90),
                                     "horz": round(rnd.uniform(0, 16), 3)}})
    return recs


def scenes(work, names):
    """name -> (scene file, size, camera flags). Writes the generated ones."""
    write_checker(work)
    # The plane: 400 x 400 units of 1-unit texels, from z = -1 to -401.
    write_json(os.path.join(work, "plane.json"), [
        {"vertices": [[-200, 0, -1], [200, 0, -1], [200, 0, -401], [-200, 0, -401]],
         "color": [128, 128, 128], "pattern": {"file": "checker.pat", "incr": 1}}])
    # The wall: 16 x 12 texels of 1 unit, seen from 8 units, slightly turned.
    write_json(os.path.join(work, "wall.json"), [
        {"vertices": [[-8, -6, -10], [8, -6, -7], [8, 6, -7], [-8, 6, -10]],
         "color": [128, 128, 128], "pattern": {"file": "checker.pat", "incr": 1, "rotate": 7}}])
    write_json(os.path.join(work, "tiles.json"), tiles())
    write_photo(work)
    # The photograph on the plane's ground (one copy every 51.2 units, texels
    # of 0.05 units: 20 texels a unit, minified to its horizon) and wrapped
    # once around a GLU sphere of radius 1 filling the frame's height.
    photo_plane = [{"vertices": [[-200, 0, -1], [200, 0, -1], [200, 0, -401], [-200, 0, -401]],
                    "color": [128, 128, 128], "pattern": {"file": "photo.png", "incr": 0.05}}]
    photo_sphere = [{"sphere": {"radius": 1, "slices": 64, "stacks": 32},
                     "transform": [{"rotate": -90, "axis": "x"}],
                     "color": [255, 255, 255], "pattern": {"file": "photo.png", "mode": "uv"}}]
    for name, recs in (("photo-plane", photo_plane), ("photo-sphere", photo_sphere)):
        write_json(os.path.join(work, f"{name}.json"), recs)
        write_json(os.path.join(work, f"{name}-standin.json"), with_standin(recs))
    ex = os.path.join(ROOT, "examples", "scenes")
    all_scenes = {
        "plane": (os.path.join(work, "plane.json"), "320x240",
                  ["--perspective", "60,1.333,0.5,1000", "--lookat", "0,2,0,0,1.2,-20"]),
        "wall": (os.path.join(work, "wall.json"), "640x480",
                 ["--perspective", "60,1.333,0.5,100", "--lookat", "0,0,0,0,0,-10"]),
        "demo2": (os.path.join(ex, "demo2.json"), "1024x768",
                  ["--perspective", "55,1,0,1000", "--lookat", "0,100,-5,0,0,-900", "--cull", "back"]),
        # Demo 1 as examples/Makefile draws it (IRIS screen patterns).
        "demo1": (os.path.join(ex, "demo1.json"), "1024x768",
                  ["--ortho2", "0,1023,0,767", "--background", "255,255,255"]),
        "tiles": (os.path.join(work, "tiles.json"), "640x480",
                  ["--perspective", "60,1.333,0.1,100", "--lookat", "0,1.2,0,0,0,-12"]),
        "photo-plane": (os.path.join(work, "photo-plane.json"), "640x480",
                        ["--perspective", "60,1.333,0.5,1000", "--lookat", "0,2,0,0,1.2,-20"]),
        "photo-sphere": (os.path.join(work, "photo-sphere.json"), "640x480",
                         ["--perspective", "45,1.333,0.5,10", "--lookat", "0,0,2.8,0,0,0"]),
    }
    return {n: all_scenes[n] for n in names}


def read_records(path):
    text = open(path).read()
    s = text.lstrip()
    if s.startswith("["):
        return json.loads(s)
    return [json.loads(line) for line in text.splitlines() if line.strip()]


def scaled(path, factor, out):
    """The scene with every object pattern's "incr" times factor and pattern
    paths made absolute (the copy lives elsewhere). Returns False when the
    scene has no object-mode pattern (nothing for polyfill3 to cut)."""
    base = os.path.dirname(os.path.abspath(path))
    recs, any_object = [], False
    for r in read_records(path):
        p = r.get("pattern")
        if p:
            p = dict(p)
            if "file" in p:
                p["file"] = os.path.normpath(os.path.join(base, p["file"]))
            if p.get("mode", "object") == "object" and "uv" not in r:
                any_object = True
                p["incr"] = p.get("incr", 1.0) * factor
            r = dict(r, pattern=p)
        recs.append(r)
    write_json(out, recs)
    return any_object


def standin_of(scene):
    """The stand-in scene written beside a photograph scene (with_standin)."""
    return scene[:-len(".json")] + "-standin.json"


def filter_methods(sr):
    """One method per --filter value when scene-render has the flag (it is
    being added on another branch): parsed from its --help."""
    text = subprocess.run([sr, "--help"], capture_output=True, text=True).stdout
    lines = text.splitlines()
    start = next((i for i, l in enumerate(lines) if l.strip().startswith("--filter ")), None)
    if start is None:
        return []
    values = []
    for l in lines[start + 1:]:
        # The next option's header (indented 2 to 6 columns; descriptions,
        # which may begin with a flag name, are indented 10).
        if re.match(r"^ {2,6}-", l):
            break
        t = l.strip()
        if t.startswith("[possible values:"):
            values = [v.strip() for v in t[len("[possible values:"):].rstrip("]").split(",")]
            break
        if t.startswith("- "):
            values.append(t[2:].split(":")[0].strip())
    # box is the default: the "direct --aa exact" row already.
    return [{"name": f"direct --filter {v}", "kind": "direct", "args": ["--aa", "exact", "--filter", v]}
            for v in values if v and v != "box"]


def timed(cmd, shell=False):
    """(wall seconds, the run) of one run of `cmd` (a shell command line
    when `shell`), with its output kept (bench/timing.py)."""
    r = run_logged(["sh", "-c", cmd] if shell else cmd, keep_stdout=True)
    return r.wall, r


def sr_render_time(stderr):
    try:
        return float(stderr.split("render ")[1].split(" s")[0])
    except (IndexError, ValueError):
        return None


def measure(sr, image, ref):
    out = subprocess.run([sr, "--image", image, "--compare", ref, "--json"], check=True,
                         capture_output=True, text=True).stdout
    return json.loads(out)["compare"]


class Runner:
    def __init__(self, bins, work, runs, python):
        self.sr = os.path.join(bins, "scene-render")
        self.p3 = os.path.join(bins, "polyfill3")
        self.pat_tile = os.path.join(bins, "pat-tile")
        self.work, self.runs, self.python = work, runs, python
        self.notes = []
        # (scene, method) run SLOW_RUNS times only.
        self.slow = set()
        # The polyfill3 --uv streams made in this run.
        self.made = set()

    def reference(self, name, scene, size, cam):
        ref = os.path.join(self.work, f"{name}-ref.png")
        dt, r = timed([self.sr, "--size", size, *cam, "--reference", "--json", scene, "-o", ref])
        est = json.loads(r.stdout)["reference"]
        self.notes.append(f"{name}: reference in {dt:.2f} s (one run), own error estimate "
                          f"{est['max_linear']:.1e} linear, {est['max_codes']} 8-bit code(s), "
                          f"{est['uncertain_pixels']} uncertain pixel(s)")
        return ref, dt

    def run(self, m, name, scene, size, cam, ref):
        """(whole s, render-only s or None, compare dict) or None when the
        method does not apply to the scene."""
        slug = "".join(c if c.isalnum() else "-" for c in m["name"])
        img = os.path.join(self.work, f"{name}-{slug}.png")
        base = [self.sr, "--size", size, *cam]
        if m["kind"] == "direct":
            cmd, shell = base + m["args"] + ["--timings", scene, "-o", img], False
        elif m["kind"] == "p3":
            src = os.path.join(self.work, f"{name}-x{m['factor']}.json")
            # polyfill3 cuts .pat files only: no such row for a photograph.
            if os.path.exists(standin_of(scene)) or not scaled(scene, m["factor"], src):
                return None
            q = " ".join("'%s'" % a for a in base)
            cmd, shell = f"'{self.p3}' '{src}' | {q} --aa exact --timings - -o '{img}'", True
        elif m["kind"] == "llvmpipe":
            uv = os.path.join(self.work, f"{name}-uv.json")
            # Made once per scene and run (never reused from an earlier run:
            # the generated scenes may have changed).
            if uv not in self.made:
                self.made.add(uv)
                standin = standin_of(scene)
                src = standin if os.path.exists(standin) else scene
                dt, _ = timed([self.p3, "--uv", src, "-o", uv])
                self.notes.append(f"{name}: polyfill3 --uv (once, not in llvmpipe's times) {dt:.3f} s")
                if src == standin:
                    photo = os.path.join(os.path.dirname(os.path.abspath(scene)), "photo.png")
                    recs = [r if "pattern" not in r else
                            dict(r, pattern=dict(r["pattern"], file=photo)) for r in read_records(uv)]
                    write_json(uv, recs)
            cmd = [self.python, os.path.join(HERE, "llvmpipe_texture.py"), uv, "--size", size,
                   *cam, "--filter", m["filter"], "--msaa", str(m["msaa"]),
                   "--pat-tile", self.pat_tile, "-o", img]
            shell = False
        else:
            raise ValueError(f"unknown method kind {m['kind']!r}")
        # The warm-up run also tells a slow method (bench/timing.py's rule:
        # the median of the runs after one warm-up).
        def runs(warm):
            if warm > SLOW_RUN_S and SLOW_RUNS < self.runs:
                self.slow.add((name, m["name"]))
                return SLOW_RUNS
            return self.runs

        if m["kind"] == "llvmpipe":
            render = lambda r: json.loads(r.stdout)["render_s"]  # noqa: E731
        else:
            render = lambda r: sr_render_time(r.stderr)  # noqa: E731
        whole, render_s, _ = medians(["sh", "-c", cmd] if shell else cmd, render, runs=runs,
                                     keep_stdout=True)
        return whole, render_s, measure(self.sr, img, ref)


def md(label):
    """A label inside a Markdown table cell."""
    return label.replace("|", "\\|")


def fmt_t(t):
    return "" if t is None else f"{t:.3f}"


def fmt_err(c):
    psnr = "inf" if c["psnr"] is None else f"{c['psnr']:.2f}"
    return f"{c['rmse']:.4f} | {psnr} | {c['largest_error']} | {100 * c['share_off']:.3f}%"


def header(runs):
    import platform
    cpu = next((l.split(":", 1)[1].strip() for l in open("/proc/cpuinfo") if l.startswith("model name")), "?")
    load = " ".join(open("/proc/loadavg").read().split()[:3])
    commit = subprocess.run(["git", "-C", ROOT, "rev-parse", "--short", "HEAD"], capture_output=True,
                            text=True).stdout.strip()
    dirty = subprocess.run(["git", "-C", ROOT, "status", "--porcelain", "--untracked-files=no"],
                           capture_output=True, text=True).stdout.strip()
    print(f"Run {time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())} on {platform.system()} "
          f"{platform.machine()}, {os.cpu_count()} cores ({cpu}), load average {load} at the start.")
    print(f"Commit {commit}{' (with uncommitted changes)' if dirty else ''}. The machine is shared with "
          "other jobs: compare ratios within this run rather than times across runs.")
    print(f"Times: median of {runs} runs after a warm-up ({SLOW_RUNS} when the warm-up takes over "
          f"{SLOW_RUN_S:g} s; marked), bench/timing.py's rule. 'whole' is the wall-clock time of the whole process "
          "(start, read, render, write the PNG; for polyfill3 rows the whole pipeline "
          "`polyfill3 | scene-render`; for llvmpipe the Python process: start, imports, reading the "
          "uv stream, pat-tile for the texels, EGL context, render, PNG). 'render' is the render-only "
          "time the tool reports (scene-render --timings' render phase; for polyfill3 rows scene-render's "
          "only; llvmpipe: shader compile, texture and vertex upload, draw, MSAA resolve, read back).")
    print("Errors against `scene-render --reference` in 8-bit sRGB units over RGB: RMSE, PSNR, "
          "largest error, share of pixels off by more than 4.")
    print()


TEXTURE_SCENES = ["plane", "wall", "demo2", "photo-plane", "photo-sphere"]


def texture_report(bins, work, python, names):
    runner = Runner(bins, work, 3, python)
    methods = TEXTURE_METHODS + filter_methods(runner.sr)
    print("# Direct texturing benchmark (issues 7 and 19)")
    print()
    header(3)
    print(f"The photo scenes texture with NASA's Blue Marble ({os.path.relpath(PHOTO_SOURCE, ROOT)}) "
          f"resampled to {PHOTO_SIDE}x{PHOTO_SIDE} PNG, an image texture (no .pat): llvmpipe draws the same "
          "texels as an sRGB8 texture; polyfill3 cuts .pat files only, so those scenes have no polyfill3 "
          "row (llvmpipe's uv stream comes from `polyfill3 --uv` on the scene with a stand-in .pat of the "
          "same side, the texel coordinates being the same).")
    print()
    sc = scenes(work, names or TEXTURE_SCENES)
    goals = []
    for name, (scene, size, cam) in sc.items():
        ref, t_ref = runner.reference(name, scene, size, cam)
        res = {}
        for m in methods:
            r = runner.run(m, name, scene, size, cam, ref)
            if r:
                res[m["name"]] = r
        tri = res["llvmpipe trilinear"]
        print(f"## {name} ({size}, {os.path.basename(scene)})")
        print()
        print("| path | render s | whole s | RMSE | PSNR dB | max | off>4 | render / llvmpipe trilinear's | whole / llvmpipe trilinear's |")
        print("|---|---:|---:|---:|---:|---:|---:|---:|---:|")
        print(f"| reference | | {t_ref:.3f} | 0 | inf | 0 | 0% | | {t_ref / tri[0]:.2f} |")
        for label, (w, r, c) in res.items():
            rr = f"{r / tri[1]:.2f}" if r is not None and tri[1] else ""
            mark = f" ({SLOW_RUNS} runs)" if (name, label) in runner.slow else ""
            print(f"| {md(label)}{mark} | {fmt_t(r)} | {w:.3f} | {fmt_err(c)} | {rr} | {w / tri[0]:.2f} |")
        print()
        d = res[next(m["name"] for m in methods if m.get("default"))]
        llv = {k: v for k, v in res.items() if k.startswith("llvmpipe")}
        best_name, best = min(llv.items(), key=lambda kv: kv[1][2]["rmse"])
        p3 = res.get("polyfill3 incr x1 | exact")
        lines = []
        ok1 = d[2]["rmse"] <= 0.1 * best[2]["rmse"]
        lines.append(f"error: default RMSE {d[2]['rmse']:.4f} vs llvmpipe's best ({best_name}) "
                     f"{best[2]['rmse']:.4f}: ratio {d[2]['rmse'] / best[2]['rmse']:.4f} "
                     f"(goal <= 0.1): {'met' if ok1 else 'NOT met'}")
        ok2 = d[1] <= 2 * tri[1]
        lines.append(f"render time: default {d[1]:.3f} s vs llvmpipe trilinear {tri[1]:.3f} s: ratio "
                     f"{d[1] / tri[1]:.2f} (goal <= 2): {'met' if ok2 else 'NOT met'}")
        ok3 = d[0] < tri[0]
        lines.append(f"whole process: default {d[0]:.3f} s vs llvmpipe trilinear {tri[0]:.3f} s: ratio "
                     f"{d[0] / tri[0]:.2f} (goal < 1): {'met' if ok3 else 'NOT met'}")
        if p3:
            ok4 = d[0] < p3[0] and d[2]["rmse"] <= p3[2]["rmse"]
            lines.append(f"direct vs polyfill3 | scene-render: whole {d[0]:.3f} s vs {p3[0]:.3f} s "
                         f"(ratio {d[0] / p3[0]:.2f}), RMSE {d[2]['rmse']:.4f} vs {p3[2]['rmse']:.4f} "
                         f"(goal: faster at equal or lower error): {'met' if ok4 else 'NOT met'}")
        else:
            ok4 = None
        print(f"Goals on {name}:")
        print()
        for l in lines:
            print(f"- {l}")
        print()
        goals.append((name, ok1, ok2, ok3, ok4))
    print("## Goals, all scenes")
    print()
    print("| scene | error <= 0.1 x llvmpipe's best | render <= 2 x llvmpipe trilinear | whole < llvmpipe trilinear | direct beats polyfill3 path |")
    print("|---|---|---|---|---|")
    for name, *oks in goals:
        print(f"| {name} | " + " | ".join("n/a" if o is None else "met" if o else "not met" for o in oks)
              + " |")
    print()
    notes(runner, methods)


def notes(runner, methods):
    print("Notes:")
    print()
    info = subprocess.run([runner.python, "-c", "import moderngl; c = moderngl.create_standalone_context("
                           "backend='egl'); print(c.info['GL_RENDERER'], '|', c.info['GL_VERSION'], '|', "
                           "c.max_anisotropy, '|', c.max_samples)"], capture_output=True, text=True).stdout
    rend, ver, aniso, samples = [x.strip() for x in info.split("|")]
    print(f"- peer: {rend}, OpenGL {ver}; GL_MAX_TEXTURE_MAX_ANISOTROPY {aniso} (the 16x rows are real "
          f"16x anisotropic filtering), max MSAA samples {samples}. sRGB8_ALPHA8 textures and framebuffer "
          "(GL_FRAMEBUFFER_SRGB), wrap REPEAT, mipmaps by glGenerateMipmap, transparent texels discarded "
          "at alpha < 0.5.")
    if not any(m["name"].startswith("direct --filter") for m in methods):
        print("- scene-render on this commit has no --filter: its rows are the exact box filter only "
              "(the script adds one row per --filter value when the flag is there).")
    print("- GL_LINEAR magnification interpolates between texel centres: where a texel covers many "
          "pixels (the plane's near rows, the wall, demo 2's pyramid) the trilinear rows blur the crisp "
          "texels of the reference, which is most of their error; nearest keeps them crisp but aliases "
          "where texels are minified.")
    for n in runner.notes:
        print(f"- {n}")


def tradeoff(bins, work, png, python):
    runner = Runner(bins, work, 5, python)
    methods = METHODS + filter_methods(runner.sr)
    print("# Run time against error: the trade-off study (issue 5)")
    print()
    header(5)
    print("polyfill3 rows multiply every object pattern's incr (texel side) by the factor: x1 is the "
          "scene itself; other factors draw the pattern at another scale, so their error is that of a "
          "different texture (what a coarser or finer incr costs), not of an approximation of the same one.")
    print()
    print(f"![time against error](../docs/{os.path.basename(png)})")
    print()
    sc = scenes(work, ["plane", "wall", "demo2", "demo1", "tiles"])
    rows = []
    for name, (scene, size, cam) in sc.items():
        ref, t_ref = runner.reference(name, scene, size, cam)
        rows.append((name, "reference", t_ref, None, {"rmse": 0.0, "psnr": None, "largest_error": 0,
                                                      "share_off": 0.0}))
        for m in methods:
            r = runner.run(m, name, scene, size, cam, ref)
            if r:
                rows.append((name, m["name"], *r))
        print(f"[{name} done]", file=sys.stderr)
    print("| scene | method | whole s | render s | RMSE | PSNR dB | max | off>4 | Pareto |")
    print("|---|---|---:|---:|---:|---:|---:|---:|---|")
    front = pareto(rows)
    for row in rows:
        name, label, w, r, c = row
        mark = f" ({SLOW_RUNS} runs)" if (name, label) in runner.slow else ""
        print(f"| {name} | {md(label)}{mark} | {w:.3f} | {fmt_t(r)} | {fmt_err(c)} | {'yes' if (name, label) in front else ''} |")
    print()
    print("Pareto: no other method on the same scene is at least as fast (whole process) and at least as "
          "accurate (RMSE), and better in one (the reference's single run counts as its time).")
    print()
    notes(runner, methods)
    print("- demo 1 uses IRIS screen-mode patterns: llvmpipe fetches texels at the window position, so "
          "its three filters draw the same; polyfill3 passes screen patterns through (no incr sweep).")
    print(f"- The plot draws RMSE 0 at {RMSE_FLOOR:g} (log axis), as hollow marks.")
    plot(rows, front, png)


def pareto(rows):
    front = set()
    for name, label, w, r, c in rows:
        dominated = any(n2 == name and (w2 <= w and c2["rmse"] <= c["rmse"]) and (w2 < w or c2["rmse"] < c["rmse"])
                        for n2, l2, w2, r2, c2 in rows)
        if not dominated:
            front.add((name, label))
    return front


def family(label):
    for key in ("reference", "polyfill3", "llvmpipe", "--filter", "direct"):
        if key in label:
            return key
    return "other"


def plot(rows, front, png, date=None):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import matplotlib.ticker
    names = list(dict.fromkeys(r[0] for r in rows))
    cols = 3
    nrows = (len(names) + 1 + cols - 1) // cols  # one cell left for the legend
    fig, grid = plt.subplots(nrows, cols, figsize=(5.2 * cols, 4.4 * nrows), squeeze=False)
    cells = list(grid.flat)
    axes, legend_ax = cells[:len(names)], cells[-1]
    for ax in cells[len(names):]:
        ax.axis("off")
    style = {"direct": ("o", "tab:blue"), "--filter": ("D", "tab:cyan"), "polyfill3": ("s", "tab:green"),
             "llvmpipe": ("^", "tab:red"), "reference": ("*", "black"), "other": ("x", "tab:purple")}
    labels = []
    for ax, name in zip(axes, names):
        pts = [r for r in rows if r[0] == name]
        for _, label, w, _, c in pts:
            y = max(c["rmse"], RMSE_FLOOR)
            mk, col = style[family(label)]
            ax.scatter([w], [y], marker=mk, color=col, s=36, zorder=3,
                       facecolors="none" if c["rmse"] == 0 else col)
            short = (label.replace("direct ", "").replace(" (default)", "*").replace("polyfill3 incr ", "p3 ")
                     .replace(" | exact", "").replace("llvmpipe ", "gl ").replace(" MSAA 4x", "+ms4")
                     .replace("trilinear", "tri").replace("nearest", "near").replace("aniso16", "ani16")
                     .replace("--filter ", "f:").replace("--aa ", ""))
            labels.append((ax, w, y, short))
        fr = sorted(((w, max(c["rmse"], RMSE_FLOOR)) for n, l, w, _, c in pts if (n, l) in front))
        if fr:
            xs, ys = [], []
            for i, (x, y) in enumerate(fr):
                if i:
                    xs.append(x)
                    ys.append(ys[-1])
                xs.append(x)
                ys.append(y)
            ax.plot(xs, ys, color="gray", lw=1, ls="--", zorder=2)
        ax.axhline(RMSE_FLOOR, color="lightgray", lw=0.8)
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_title(name)
        ax.set_xlabel("whole process, s (median)")
        ax.set_ylabel("RMSE vs reference (8-bit sRGB)")
        ax.xaxis.set_minor_formatter(matplotlib.ticker.NullFormatter())
        ax.set_ylim(RMSE_FLOOR / 3, 300)
        ax.grid(True, which="both", lw=0.3, alpha=0.5)
    handles = [plt.Line2D([], [], marker=m, color=c, ls="", label=k) for k, (m, c) in style.items()
               if k != "other"]
    handles.append(plt.Line2D([], [], color="gray", ls="--", label="Pareto front"))
    legend_ax.legend(handles=handles, loc="center", fontsize=9,
                     title=f"RMSE 0 drawn hollow at {RMSE_FLOOR:g}\n* = default mode; gl = llvmpipe;\n"
                           "p3 xF = polyfill3, incr x F | exact;\nf: = --filter; ms4 = MSAA 4x")
    date = date or time.strftime('%Y-%m-%d', time.gmtime())
    fig.suptitle(f"patkit trade-off: time against error ({date}, {os.cpu_count()} cores, shared machine)",
                 fontsize=10)
    fig.tight_layout(rect=(0, 0, 1, 0.96))
    place_labels(fig, labels)
    fig.savefig(png, dpi=110)


def place_labels(fig, labels):
    """Writes each point's label where it overlaps no label placed before it:
    the first free slot of a few above, below and left of the point, joined
    to it by a thin line when it had to move; points are taken from the top
    of each panel down. Clustered points (the filters, llvmpipe's modes) had
    their labels printed over one another."""
    import matplotlib.text
    renderer = fig.canvas.get_renderer()
    placed = {}
    slots = [(4, 2, "left")] + [(4, 2 + s * d, "left") for d in range(1, 9) for s in (-9, 9)] \
        + [(-4, 2 + s * d, "right") for d in range(0, 9) for s in (9, -9)]
    for ax, x, y, text in sorted(labels, key=lambda l: (id(l[0]), -l[2], l[1])):
        taken = placed.setdefault(id(ax), [])
        for dx, dy, ha in slots:
            moved = (dx, dy) != (4, 2)
            ann = ax.annotate(text, (x, y), fontsize=6, xytext=(dx, dy), textcoords="offset points", ha=ha,
                              va="bottom", annotation_clip=False,
                              arrowprops=dict(arrowstyle="-", lw=0.3, color="gray") if moved else None)
            # The text's own box (the annotation's includes its leader
            # line), once the annotation has placed it.
            ann.update_positions(renderer)
            box = matplotlib.text.Text.get_window_extent(ann, renderer).expanded(1.05, 1.1)
            inside = ax.get_window_extent(renderer)
            if not any(box.overlaps(b) for b in taken) and inside.contains(box.x0, box.y0) \
                    and inside.contains(box.x1, box.y1):
                taken.append(box)
                break
            ann.remove()
        else:
            print("UNPLACED", text, file=sys.stderr)
            ax.annotate(text, (x, y), fontsize=6, xytext=(4, 2), textcoords="offset points")


def replot(results_md, png):
    """Draws the plot again from a RESULTS-tradeoff.md table (no rerun)."""
    rows, front, date = [], set(), None
    for line in open(results_md):
        if line.startswith("Run ") and date is None:
            m = re.search(r"(\d{4}-\d{2}-\d{2})", line)
            date = m.group(1) if m else None
        if not line.startswith("| ") or line.startswith("| scene"):
            continue
        cells = [c.strip().replace("\\|", "|") for c in re.split(r"(?<!\\)\|", line.strip())[1:-1]]
        name, label, whole, _, rmse = cells[:5]
        label = re.sub(r" \(\d+ runs\)$", "", label)
        rows.append((name, label, float(whole), None, {"rmse": float(rmse)}))
        if cells[-1] == "yes":
            front.add((name, label))
    plot(rows, front, png, date)


def main():
    mode = sys.argv[1]
    if mode == "texture":
        texture_report(sys.argv[2], sys.argv[3], sys.executable, sys.argv[4:])
    elif mode == "replot":
        replot(sys.argv[2], sys.argv[3])
    elif mode == "tradeoff":
        tradeoff(sys.argv[2], sys.argv[3], sys.argv[4], sys.executable)
    else:
        sys.exit(f"texbench.py: unknown mode {mode!r}: expected texture or tradeoff")


if __name__ == "__main__":
    main()
