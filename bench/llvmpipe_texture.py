#!/usr/bin/env python3
"""The textured peer of the benchmarks: draws a `polyfill3 --uv` stream with
Mesa's llvmpipe (moderngl, EGL standalone context, no display), the way an
OpenGL program would, and writes a PNG that `scene-render --compare` measures.

    llvmpipe_texture.py STREAM --size WxH [camera] --filter nearest|trilinear|aniso16
                        [--msaa 0|4] [--cull back] [--background R,G,B]
                        --pat-tile PATH -o OUT.png

What is drawn (docs/rendering.md's model through OpenGL):
- "uv" records: per-vertex texture coordinates in texel units, divided by the
  texture's width and height; one tile of the pattern as an sRGB8_ALPHA8
  texture (from `pat-tile --size SxS`, rows flipped: the image's top row is
  the pattern's last row, GL's row 0 is the bottom), or an image texture's
  own pixels (Pillow, rows flipped the same way), wrap REPEAT,
  perspective-correct interpolation (GL's default for `in` variables).
- "screen" records (demo 1's IRIS patterns): `texelFetch` at the window
  position modulo SIZE, pixel (0, 0) at the lower left as scene-render places them.
- records without a pattern: their flat colour.
Transparent texels are discarded where the filtered alpha is below one half
(the alpha test of fixed-function GL), showing what lies behind.

Filters: nearest (GL_NEAREST, no mipmaps), trilinear (GL_LINEAR_MIPMAP_LINEAR,
GL_LINEAR, glGenerateMipmap) and aniso16 (trilinear with
GL_TEXTURE_MAX_ANISOTROPY 16; refused if the driver offers less).

The framebuffer is sRGB8_ALPHA8 with GL_FRAMEBUFFER_SRGB enabled, so shading
writes linear light that is encoded on store, the MSAA resolve (a blit)
averages in linear light, and the read back is 8-bit sRGB: scene-render's rules.

Prints one JSON object: the render-only time (texture and vertex upload, draw,
MSAA resolve, read back; seconds), the time before it (Python start, imports,
reading the stream, pat-tile) and after it (PNG encode and write), the filter
and the driver's maximum anisotropy. The whole process is timed by the caller.
"""
import time

T_START = time.perf_counter()

import argparse  # noqa: E402
import json  # noqa: E402
import os  # noqa: E402
import subprocess  # noqa: E402
import sys  # noqa: E402

import numpy as np  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from scene_render_bench import lookat, ortho, perspective, save_png, srgb_to_linear  # noqa: E402

# GL_SRGB8_ALPHA8 and GL_FRAMEBUFFER_SRGB (OpenGL 4.5 core, tables 8.13, 17.x).
GL_SRGB8_ALPHA8 = 0x8C43
GL_FRAMEBUFFER_SRGB = 0x8DB9
# The anisotropy of the third column.
ANISOTROPY = 16.0
# OpenGL's perspective cannot take near = 0 (the depth mapping divides by it);
# scene-render's can (demo 2 uses it). near = far / NEAR_FRACTION then: for
# demo 2 that is 1 unit, and its nearest visible point is ~100 units away.
NEAR_FRACTION = 1000.0
# Alpha below this is a transparent texel: discarded (GL's alpha test).
ALPHA_CUTOFF = 0.5

VS = """#version 330
uniform mat4 mvp;
in vec3 in_pos; in vec2 in_uv; in vec3 in_col;
out vec2 uv; out vec3 col;
void main() { gl_Position = mvp * vec4(in_pos, 1.0); uv = in_uv; col = in_col; }"""
FS = """#version 330
uniform sampler2D tex;
uniform int mode;      // 0 flat colour, 1 uv, 2 screen
uniform vec2 size;     // the texture's width and height in texels
uniform float cutoff;
in vec2 uv; in vec3 col; out vec4 frag;
void main() {
    if (mode == 0) { frag = vec4(col, 1.0); return; }
    vec4 t;
    if (mode == 1) {
        t = texture(tex, uv / size);
    } else {
        ivec2 p = ivec2(gl_FragCoord.xy) % ivec2(size);
        t = texelFetch(tex, p, 0);
    }
    if (t.a < cutoff) discard;
    frag = vec4(t.rgb, 1.0);
}"""


def parse_args(argv):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("stream")
    ap.add_argument("--size", required=True)
    ap.add_argument("--perspective", help="fovy,aspect,near,far (degrees)")
    ap.add_argument("--lookat", help="ex,ey,ez,cx,cy,cz")
    ap.add_argument("--ortho2", help="l,r,b,t")
    ap.add_argument("--cull", choices=["back"])
    ap.add_argument("--background", default="0,0,0")
    ap.add_argument("--filter", required=True, choices=["nearest", "trilinear", "aniso16"])
    ap.add_argument("--msaa", type=int, default=0, choices=[0, 4])
    ap.add_argument("--pat-tile", required=True, help="path of the pat-tile binary")
    ap.add_argument("-o", "--output", required=True)
    return ap.parse_args(argv)


def floats(s, n, name):
    v = [float(x) for x in s.split(",")]
    if len(v) != n or not all(np.isfinite(v)):
        sys.exit(f"llvmpipe_texture: --{name} {s}: expected {n} finite numbers")
    return v


def camera(a, w, h):
    if a.perspective:
        fovy, aspect, near, far = floats(a.perspective, 4, "perspective")
        if near <= 0:
            near = far / NEAR_FRACTION
        view = lookat(*floats(a.lookat, 6, "lookat")) if a.lookat else np.identity(4)
        return perspective(fovy, aspect, near, far) @ view
    if a.ortho2:
        left, right, bottom, top = floats(a.ortho2, 4, "ortho2")
        return ortho(left, right, bottom, top, -1, 1)
    return ortho(0, w, 0, h, -1, 1)


def read_pam(data):
    """A PAM (P7) of RGB or RGB_ALPHA: rows top first, as an HxWx4 uint8."""
    end = data.index(b"ENDHDR\n") + len(b"ENDHDR\n")
    hdr = dict(line.split(" ", 1) for line in data[:end].decode().splitlines()[1:-1])
    w, h, d = int(hdr["WIDTH"]), int(hdr["HEIGHT"]), int(hdr["DEPTH"])
    px = np.frombuffer(data[end:end + w * h * d], dtype=np.uint8).reshape(h, w, d)
    if d == 3:
        px = np.concatenate([px, np.full((h, w, 1), 255, np.uint8)], axis=2)
    return px


def texels(pat_tile, path):
    """One tile of the texture in GL row order (row 0 = the texture's row 0,
    the bottom), and its (width, height) in texels. A .pat through pat-tile;
    any other file is an image texture (issue 19), read with Pillow: its
    bottom row is texel row 0, as scene-render places it."""
    if not path.endswith(".pat"):
        from PIL import Image
        img = np.asarray(Image.open(path).convert("RGBA"))
        return np.ascontiguousarray(img[::-1]), (img.shape[1], img.shape[0])
    with open(path) as fh:
        size = int(fh.readline().split()[0])
    out = subprocess.run([pat_tile, "--size", f"{size}x{size}", "--format", "pam", path, "-o", "-"],
                         check=True, capture_output=True).stdout
    img = read_pam(out)
    return np.ascontiguousarray(img[::-1]), (size, size)


def load(stream):
    """Fan-triangulated geometry grouped by (mode, pattern file): per group a
    float32 array of x, y, z, u, v, r, g, b (colour in linear light)."""
    groups = {}
    with open(stream) as fh:
        for n, line in enumerate(fh):
            if not line.strip():
                continue
            r = json.loads(line)
            if "vertices" not in r:
                sys.exit(f"llvmpipe_texture: {stream}: record {n}: no \"vertices\" "
                         "(objects and curves: run polyfill3 --uv first)")
            v = [p if len(p) == 3 else [p[0], p[1], 0.0] for p in r["vertices"]]
            pat = r.get("pattern")
            mode, key = 0, None
            if pat:
                mode = 1 if pat.get("mode") == "uv" else 2 if pat.get("mode") == "screen" else None
                if mode is None:
                    sys.exit(f"llvmpipe_texture: {stream}: record {n}: pattern mode "
                             f"{pat.get('mode', 'object')!r} (run polyfill3 --uv first)")
                key = pat["file"]
            uv = r.get("uv") if mode == 1 else None
            if uv is None:
                uv = [[0.0, 0.0]] * len(v)
            col = srgb_to_linear(r.get("color", [0, 0, 0]))
            rows = groups.setdefault((mode, key), [])
            for i in range(1, len(v) - 1):
                for k in (0, i, i + 1):
                    rows.append([*v[k], *uv[k], *col])
    return {k: np.array(rows, dtype="f4") for k, rows in groups.items()}


def render(ctx, groups, textures, mvp, w, h, a):
    import moderngl
    prog = ctx.program(vertex_shader=VS, fragment_shader=FS)
    prog["mvp"].write(mvp.T.astype("f4").tobytes())
    prog["cutoff"].value = ALPHA_CUTOFF
    released = [prog]
    gl_tex = {}
    for key, (img, size) in textures.items():
        t = ctx.texture(size, 4, img.tobytes(), internal_format=GL_SRGB8_ALPHA8)
        t.repeat_x = t.repeat_y = True
        if a.filter == "nearest":
            t.filter = (moderngl.NEAREST, moderngl.NEAREST)
        else:
            t.build_mipmaps()
            t.filter = (moderngl.LINEAR_MIPMAP_LINEAR, moderngl.LINEAR)
            if a.filter == "aniso16":
                t.anisotropy = ANISOTROPY
        gl_tex[key] = t
        released.append(t)
    col = ctx.texture((w, h), 4, samples=a.msaa, internal_format=GL_SRGB8_ALPHA8)
    dep = ctx.depth_renderbuffer((w, h), samples=a.msaa)
    fbo = ctx.framebuffer(color_attachments=[col], depth_attachment=dep)
    released += [col, dep, fbo]
    if a.msaa:
        res_col = ctx.texture((w, h), 4, internal_format=GL_SRGB8_ALPHA8)
        res = ctx.framebuffer(color_attachments=[res_col])
        released += [res_col, res]
    else:
        res = fbo
    ctx.enable_direct(GL_FRAMEBUFFER_SRGB)
    fbo.use()
    bg = srgb_to_linear([int(x) for x in a.background.split(",")])
    ctx.clear(bg[0], bg[1], bg[2], 1.0, depth=1.0)
    ctx.enable(moderngl.DEPTH_TEST)
    # Equal depths (2D scenes, all at z = 0): the later record wins, as in
    # scene-render's painter order.
    ctx.depth_func = "<="
    if a.cull:
        ctx.enable(moderngl.CULL_FACE)
        ctx.cull_face = "back"  # counter-clockwise fronts (as scene-render), GL's default
    else:
        ctx.disable(moderngl.CULL_FACE)
    for (mode, key), verts in groups.items():
        vbo = ctx.buffer(verts.tobytes())
        vao = ctx.vertex_array(prog, [(vbo, "3f 2f 3f", "in_pos", "in_uv", "in_col")])
        prog["mode"].value = mode
        if mode:
            gl_tex[key].use(0)
            prog["tex"].value = 0
            prog["size"].value = tuple(float(x) for x in textures[key][1])
        vao.render(moderngl.TRIANGLES)
        released += [vao, vbo]
    if a.msaa:
        ctx.copy_framebuffer(res, fbo)
    data = np.frombuffer(res.read(components=3), dtype=np.uint8).reshape(h, w, 3)
    ctx.finish()
    for o in released:
        o.release()
    return data[::-1]


def main():
    a = parse_args(sys.argv[1:])
    w, h = (int(x) for x in a.size.split("x"))
    mvp = camera(a, w, h)
    groups = load(a.stream)
    # A pattern's "file" is relative to the stream's directory, as
    # scene-render resolves it (polyfill3 --uv writes it as the scene gave it).
    base = os.path.dirname(os.path.abspath(a.stream))
    textures = {key: texels(a.pat_tile, os.path.join(base, key)) for (mode, key) in groups if mode}
    import moderngl
    ctx = moderngl.create_standalone_context(backend="egl")
    max_aniso = float(ctx.max_anisotropy)
    if a.filter == "aniso16" and max_aniso < ANISOTROPY:
        sys.exit(f"llvmpipe_texture: --filter aniso16: the driver offers anisotropy {max_aniso} only")
    t0 = time.perf_counter()
    img = render(ctx, groups, textures, mvp, w, h, a)
    t1 = time.perf_counter()
    save_png(np.ascontiguousarray(img), a.output)
    t2 = time.perf_counter()
    print(json.dumps({"render_s": t1 - t0, "before_s": t0 - T_START, "png_s": t2 - t1,
                      "filter": a.filter, "msaa": a.msaa, "max_anisotropy": max_aniso,
                      "renderer": ctx.info["GL_RENDERER"], "triangles": sum(len(g) for g in groups.values()) // 3}))


if __name__ == "__main__":
    main()
