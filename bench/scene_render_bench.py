#!/usr/bin/env python3
"""Driver of bench/scene_render.sh: times scene-render's --aa modes and Mesa's
llvmpipe (through moderngl, EGL, no display) on the same flat polygons, and
measures every image against scene-render --reference. Prints one Markdown table.

Not a test: timings depend on the machine and its load; each time is the median
of RUNS runs of the whole pipeline (read the stream, render, encode the PNG)
after a warm-up, bench/timing.py's rule.
"""
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from timing import measure_in_turns, run_logged  # noqa: E402

RUNS = 5
W, H = 1024, 768
BACKGROUND = (20, 20, 80)
# Demo 2's view (App. C): perspective(550, 1.0, 0.0, 1000.0) and
# lookat(0,100,-5, 0,0,-900, 0).
PERSPECTIVE = (55.0, 1.0, 0.0, 1000.0)
LOOKAT = (0.0, 100.0, -5.0, 0.0, 0.0, -900.0)
# OpenGL cannot take near = 0 (its depth mapping divides by near); the nearest
# visible point of demo 2 is ~100 units away, so near = 1 clips nothing.
GL_NEAR = 1.0


def srgb_to_linear(c):
    c = np.asarray(c, dtype=np.float64) / 255.0
    return np.where(c <= 0.04045, c / 12.92, ((c + 0.055) / 1.055) ** 2.4)


def linear_to_srgb8(l):
    l = np.clip(l, 0.0, 1.0)
    s = np.where(l <= 0.0031308, l * 12.92, 1.055 * np.power(l, 1.0 / 2.4) - 0.055)
    return np.round(s * 255.0).astype(np.uint8)


def perspective(fovy, aspect, near, far):
    f = 1.0 / np.tan(np.radians(fovy) / 2.0)
    return np.array([[f / aspect, 0, 0, 0], [0, f, 0, 0],
                     [0, 0, (far + near) / (near - far), 2 * far * near / (near - far)],
                     [0, 0, -1, 0]], dtype=np.float64)


def lookat(ex, ey, ez, cx, cy, cz, up=(0.0, 1.0, 0.0)):
    e, c, u = np.array([ex, ey, ez]), np.array([cx, cy, cz]), np.array(up)
    f = (c - e) / np.linalg.norm(c - e)
    s = np.cross(f, u)
    s /= np.linalg.norm(s)
    u2 = np.cross(s, f)
    m = np.identity(4)
    m[0, :3], m[1, :3], m[2, :3] = s, u2, -f
    m[:3, 3] = -m[:3, :3] @ e
    return m


def ortho(l, r, b, t, n, f):
    return np.array([[2 / (r - l), 0, 0, -(r + l) / (r - l)], [0, 2 / (t - b), 0, -(t + b) / (t - b)],
                     [0, 0, -2 / (f - n), -(f + n) / (f - n)], [0, 0, 0, 1]], dtype=np.float64)


def load_triangles(path):
    """Fan-triangulates the (convex) polygons: positions and linear colours."""
    pos, col = [], []
    with open(path) as fh:
        for line in fh:
            r = json.loads(line)
            v = r["vertices"]
            c = srgb_to_linear(r["color"])
            for i in range(1, len(v) - 1):
                for p in (v[0], v[i], v[i + 1]):
                    pos.append(p if len(p) == 3 else [p[0], p[1], 0.0])
                    col.append(c)
    return np.array(pos, dtype="f4"), np.array(col, dtype="f4")


VS = """#version 330
uniform mat4 mvp;
in vec3 in_pos; in vec3 in_col; out vec3 col;
void main() { gl_Position = mvp * vec4(in_pos, 1.0); col = in_col; }"""
FS = """#version 330
in vec3 col; out vec4 frag;
void main() { frag = vec4(col, 1.0); }"""


def llvmpipe(ctx, tris, mvp, samples, out_png, cull=False):
    """Draws linear colours into a float multisample buffer (so the MSAA resolve
    averages in linear light, as docs/rendering.md asks), reads back, encodes sRGB.
    Returns the GL time (upload, draw, resolve, read back) in seconds."""
    import moderngl
    pos, col = tris
    t0 = time.perf_counter()
    prog = ctx.program(vertex_shader=VS, fragment_shader=FS)
    prog["mvp"].write(mvp.T.astype("f4").tobytes())
    vbo = ctx.buffer(np.hstack([pos, col]).astype("f4").tobytes())
    vao = ctx.vertex_array(prog, [(vbo, "3f 3f", "in_pos", "in_col")])
    ms_col = ctx.renderbuffer((W, H), components=4, samples=samples, dtype="f4")
    ms_dep = ctx.depth_renderbuffer((W, H), samples=samples)
    fbo = ctx.framebuffer(color_attachments=[ms_col], depth_attachment=ms_dep)
    res_col = ctx.renderbuffer((W, H), components=4, dtype="f4")
    res = ctx.framebuffer(color_attachments=[res_col])
    fbo.use()
    bg = srgb_to_linear(BACKGROUND)
    ctx.clear(bg[0], bg[1], bg[2], 1.0, depth=1.0)
    ctx.enable(moderngl.DEPTH_TEST)
    ctx.depth_func = "<"
    if cull:
        # Counter-clockwise is the front (docs/stream-format.md), as GL's default.
        ctx.enable(moderngl.CULL_FACE)
        ctx.cull_face = "back"
    else:
        ctx.disable(moderngl.CULL_FACE)
    vao.render(moderngl.TRIANGLES)
    ctx.copy_framebuffer(res, fbo)
    data = np.frombuffer(res.read(components=3, dtype="f4"), dtype="f4").reshape(H, W, 3)
    t1 = time.perf_counter()
    img = linear_to_srgb8(data[::-1].astype(np.float64))
    save_png(img, out_png)
    for o in (vao, vbo, prog, fbo, res, ms_col, ms_dep, res_col):
        o.release()
    return t1 - t0


def save_png(img, path):
    import zlib
    import struct
    h, w, _ = img.shape
    raw = b"".join(b"\x00" + img[y].tobytes() for y in range(h))

    def chunk(tag, data):
        return struct.pack(">I", len(data)) + tag + data + struct.pack(">I", zlib.crc32(tag + data) & 0xffffffff)
    png = b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0))
    png += chunk(b"IDAT", zlib.compress(raw, 1)) + chunk(b"IEND", b"")
    open(path, "wb").write(png)


def median_time(cmd):
    """Median whole-pipeline time and median render-only time (--timings), of
    RUNS runs after a warm-up (bench/timing.py)."""
    (whole, phases), = measure_in_turns([cmd + ["--timings"]], RUNS)
    return whole, phases["render"]


def measure(sr, image, ref):
    out = subprocess.run([sr, "--image", image, "--compare", ref, "--json"], check=True,
                         capture_output=True, text=True).stdout
    return json.loads(out)["compare"]


def random_triangles(path, n, seed=1):
    """n random triangles of ~20 pixels each over the screen, depths in (-1, 1)
    under the default ortho2 view: a stress scene, about 27 layers deep."""
    rng = np.random.default_rng(seed)
    c = rng.random((n, 2)) * [W, H]
    a = rng.random((n, 3)) * 2 * np.pi
    r = 3.5 + rng.random((n, 1)) * 1.0
    z = rng.random((n, 1)) * 1.8 - 0.9
    col = rng.integers(0, 256, (n, 3))
    with open(path, "w") as fh:
        for i in range(n):
            v = [[round(c[i, 0] + r[i, 0] * np.cos(a[i, k]), 3), round(c[i, 1] + r[i, 0] * np.sin(a[i, k]), 3),
                  round(z[i, 0], 4)] for k in range(3)]
            fh.write(json.dumps({"vertices": v, "color": col[i].tolist()}, separators=(",", ":")) + "\n")


def main():
    if sys.argv[1] == "--random-triangles":
        random_triangles(sys.argv[3], int(sys.argv[2]))
        return
    sr, work = sys.argv[1], sys.argv[2]
    scenes = sys.argv[3:]  # name=path[:camera]
    import moderngl
    ctx = moderngl.create_standalone_context(backend="egl")
    renderer = ctx.info["GL_RENDERER"]
    max_samples = ctx.max_samples
    rows = []
    areas = {}
    notes = [f"peer: {renderer}, {ctx.info['GL_VERSION']}, max MSAA samples {max_samples}"]
    for spec in scenes:
        name, rest = spec.split("=", 1)
        path, kind = rest.split(":")
        n_polys = sum(1 for _ in open(path))
        bg = ",".join(map(str, BACKGROUND))
        cull = kind == "demo2cull"
        if kind in ("demo2", "demo2cull"):
            cam = ["--perspective", ",".join(map(str, PERSPECTIVE)), "--lookat", ",".join(map(str, LOOKAT))]
            if cull:
                cam += ["--cull", "back"]
            mvp = perspective(PERSPECTIVE[0], PERSPECTIVE[1], GL_NEAR, PERSPECTIVE[3]) @ lookat(*LOOKAT)
        else:
            cam = []
            mvp = ortho(0, W, 0, H, -1, 1)
        base = [sr, "--size", f"{W}x{H}", "--background", bg] + cam
        ref = os.path.join(work, f"{name}-reference.png")
        with_ref = kind in ("demo2", "demo2cull")
        if with_ref:
            # One run: the reference takes seconds (bench/timing.py).
            r = run_logged(base + ["--reference", "--json", path, "-o", ref], keep_stdout=True)
            t_ref = r.wall
            res = json.loads(r.stdout)["reference"]
            notes.append(f"{name}: reference in {t_ref:.1f} s, own error estimate {res['max_linear']:.1e} "
                         f"linear light, {res['max_codes']} 8-bit code(s), {res['uncertain_pixels']} uncertain pixels")
        results = {}
        for aa in ["none", "ss4", "ss16", "exact"]:
            img = os.path.join(work, f"{name}-{aa}.png")
            t, t_render = median_time(base + ["--aa", aa, path, "-o", img])
            m = measure(sr, img, ref) if with_ref else None
            results[f"scene-render --aa {aa}"] = (t, t_render, m)
        tris = load_triangles(path)
        if not with_ref:
            p = tris[0].astype(np.float64).reshape(-1, 3, 3)
            e1, e2 = p[:, 1, :2] - p[:, 0, :2], p[:, 2, :2] - p[:, 0, :2]
            areas[name] = float(np.abs(e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0]).sum() / 2)
        for samples in [0, 4]:
            img = os.path.join(work, f"{name}-llvmpipe-msaa{samples}.png")
            llvmpipe(ctx, tris, mvp, samples, img, cull)  # warm-up
            times = []
            for _ in range(RUNS):
                t0 = time.perf_counter()
                gl = llvmpipe(ctx, tris, mvp, samples, img, cull)
                times.append((time.perf_counter() - t0, gl))
            t_all = statistics.median(t[0] for t in times)
            t_gl = statistics.median(t[1] for t in times)
            m = measure(sr, img, ref) if with_ref else None
            label = "llvmpipe no MSAA" if samples == 0 else f"llvmpipe MSAA {samples}x"
            results[label] = (t_all, t_gl, m)
        peer = results.get("llvmpipe MSAA 4x")
        for label, (t, t_gl, m) in results.items():
            rows.append((name, n_polys, len(tris[0]) // 3, label, t, t_gl, m, peer))
    thr = [r for r in rows if r[0].startswith("triangles")]
    rows = [r for r in rows if not r[0].startswith("triangles")]
    print("| scene | polygons | renderer | time (s) | render only (s) | RMSE | PSNR (dB) | max | off>4 | render only / MSAA4's | RMSE / MSAA4's |")
    print("|---|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|")
    for name, n, ntri, label, t, t_gl, m, peer in rows:
        gl = f"{t_gl:.3f}" if t_gl is not None else ""
        if m:
            psnr = f"{m['psnr']:.2f}" if m["psnr"] is not None else "inf"
            err = f"{m['rmse']:.3f} | {psnr} | {m['largest_error']} | {100 * m['share_off']:.3f}%"
        else:
            err = "| | |"
        tr = f"{t_gl / peer[1]:.2f}" if peer and peer[1] and t_gl is not None else ""
        er = f"{m['rmse'] / peer[2]['rmse']:.3f}" if m and peer and peer[2] and peer[2]["rmse"] > 0 else ""
        print(f"| {name} | {n} | {label} | {t:.3f} | {gl} | {err} | {tr} | {er} |")
    if thr:
        print()
        print("| scene | triangles | covered pixels | renderer | time (s) | render only (s) | Mtriangles/s (render only) | Mpixels/s covered (render only) |")
        print("|---|---:|---:|---|---:|---:|---:|---:|")
        for name, n, ntri, label, t, t_gl, m, peer in thr:
            area = areas[name]
            gl = f"{t_gl:.3f}" if t_gl is not None else ""
            print(f"| {name} | {ntri} | {area:.3g} | {label} | {t:.3f} | {gl} | {ntri / t_gl / 1e6:.2f} | {area / t_gl / 1e6:.1f} |")
    print()
    for n in notes:
        print(f"- {n}")


if __name__ == "__main__":
    main()
