#!/usr/bin/env python3
"""llvmpipe side of bench/animate.sh: the turning pyramid drawn by Mesa's
llvmpipe (moderngl, EGL), the object's cells uploaded once and drawn per frame
through the four face instances' model matrices (the GL way of an already built
object), the plain's cells beside them; MSAA 4x into a float buffer (so the
resolve averages linear light), read back, encoded, written as PNG per frame.

Usage: animate_llvmpipe.py CELLS.ndjson FRAMES OUT_PREFIX
Prints the wall-clock seconds of the whole sequence (context setup excluded).
"""
import json
import math
import os
import sys
import time

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
# The sRGB codecs, GL matrices and PNG writer of the scene-render benchmark.
from scene_render_bench import linear_to_srgb8, lookat, perspective, save_png, srgb_to_linear  # noqa: E402

W, H = 1024, 768
SAMPLES = 4
# Demo 2's view (App. C); OpenGL cannot take near = 0, near = 1 clips nothing.
FOVY, ASPECT, NEAR, FAR = 55.0, 1.0, 1.0, 1000.0
EYE, CENTER = (0.0, 100.0, -5.0), (0.0, 0.0, -900.0)
STEP_DEG = 10.0


def rot_y(deg):
    a = math.radians(deg)
    m = np.identity(4)
    m[0, 0], m[0, 2], m[2, 0], m[2, 2] = math.cos(a), math.sin(a), -math.sin(a), math.cos(a)
    return m


def translate(x, y, z):
    m = np.identity(4)
    m[:3, 3] = (x, y, z)
    return m


def triangles(records):
    pos, col = [], []
    for r in records:
        v, c = r["vertices"], srgb_to_linear(r["color"])
        for i in range(1, len(v) - 1):
            for p in (v[0], v[i], v[i + 1]):
                pos.append(p)
                col.append(c)
    return np.hstack([np.array(pos, "f4"), np.array(col, "f4")]).astype("f4").tobytes(), len(pos)


VS = """#version 330
uniform mat4 mvp;
in vec3 in_pos; in vec3 in_col; out vec3 col;
void main() { gl_Position = mvp * vec4(in_pos, 1.0); col = in_col; }"""
FS = """#version 330
in vec3 col; out vec4 frag;
void main() { frag = vec4(col, 1.0); }"""


def main():
    import moderngl
    path, frames, prefix = sys.argv[1], int(sys.argv[2]), sys.argv[3]
    lines = [json.loads(x) for x in open(path)]
    face = lines[0]["records"]
    # The pyr object's four face instances: rotations about y (docs/objects.md).
    face_turns = [i.get("transform", {}).get("rotate", 0) for i in lines[1]["records"]]
    plain = lines[3:]
    ctx = moderngl.create_standalone_context(backend="egl")
    t0 = time.perf_counter()
    prog = ctx.program(vertex_shader=VS, fragment_shader=FS)
    vaos = []
    for recs in (face, plain):
        data, n = triangles(recs)
        vbo = ctx.buffer(data)
        vaos.append((ctx.vertex_array(prog, [(vbo, "3f 3f", "in_pos", "in_col")]), n))
    ms = ctx.framebuffer(color_attachments=[ctx.renderbuffer((W, H), components=4, samples=SAMPLES, dtype="f4")],
                         depth_attachment=ctx.depth_renderbuffer((W, H), samples=SAMPLES))
    res = ctx.framebuffer(color_attachments=[ctx.renderbuffer((W, H), components=4, dtype="f4")])
    vp = perspective(FOVY, ASPECT, NEAR, FAR) @ lookat(*EYE, *CENTER)
    ctx.enable(moderngl.DEPTH_TEST | moderngl.CULL_FACE)
    for k in range(frames):
        ms.use()
        ctx.clear(0.0, 0.0, 0.0, 1.0, depth=1.0)
        for turn in face_turns:
            m = translate(0, 0, -500) @ rot_y(STEP_DEG * k) @ rot_y(turn)
            prog["mvp"].write((vp @ m).T.astype("f4").tobytes())
            vaos[0][0].render(moderngl.TRIANGLES)
        prog["mvp"].write(vp.T.astype("f4").tobytes())
        vaos[1][0].render(moderngl.TRIANGLES)
        ctx.copy_framebuffer(res, ms)
        data = np.frombuffer(res.read(components=3, dtype="f4"), dtype="f4").reshape(H, W, 3)
        save_png(linear_to_srgb8(data[::-1].astype(np.float64)), f"{prefix}-{k:04d}.png")
    print(f"{time.perf_counter() - t0:.4f}")


if __name__ == "__main__":
    main()
