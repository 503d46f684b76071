#!/usr/bin/env python3
"""Driver of bench/large_frame.sh: a large frame with little drawn in it.
The same 10,000 random triangles (bench/random_triangles.py, `auto`, the
aa_scaling benchmark's smallest scene) fill the 1024x768 corner of frames
from 1024x1024 to 16384x16384 under scene-render's default view (pixel
coordinates), so the drawn part stays the same and the empty part grows.

    large_frame.py SCENE_RENDER WORKDIR [BASELINE_SCENE_RENDER]

For each size: scene-render --aa exact's render phase (--timings) and whole
process, median of RUNS after a warm-up, the builds taking turns
(bench/timing.py), and this build's peak resident memory; llvmpipe MSAA 4x
(upload, draw, resolve, read back) up to 4096x4096, where its float
multisample buffer is 1 GiB. Checks that the two builds' PNGs are the same
bytes.
"""
import os
import statistics
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import scene_render_bench as srb  # noqa: E402
from timing import measure, measure_in_turns  # noqa: E402

RUNS = int(os.environ.get("FRAME_RUNS", "3"))
SIZES = [1024, 4096, 8192, 16384]
# llvmpipe's MSAA 4x float buffer is 64 bytes a pixel.
LLVMPIPE_MAX = 4096


def main():
    sr, work = sys.argv[1], sys.argv[2]
    base = sys.argv[3] if len(sys.argv) > 3 else None
    here = os.path.dirname(os.path.abspath(__file__))
    scene = os.path.join(work, "tri-auto-10000.ndjson")
    if not os.path.exists(scene):
        with open(scene, "w") as fh:
            subprocess.run([sys.executable, os.path.join(here, "random_triangles.py"), "10000", "auto"],
                           stdout=fh, check=True)
    import moderngl
    ctx = moderngl.create_standalone_context(backend="egl")
    tris = srb.load_triangles(scene)
    head = "| frame | drawn | render s | whole s | peak MiB |"
    rule = "|---|---:|---:|---:|---:|"
    if base:
        head += " baseline render s | baseline whole s | render: this/baseline |"
        rule += "---:|---:|---:|"
    head += " MSAA 4x render s | render: this/MSAA 4x |"
    rule += "---:|---:|"
    print(head)
    print(rule)
    for side in SIZES:
        size = f"{side}x{side}"
        outs = [os.path.join(work, f"frame-{side}-{k}.png") for k in ("this", "base")]
        cmd = lambda exe, out: [exe, "--size", size, "--background", "20,20,80", "--aa", "exact",  # noqa: E731
                                "--timings", scene, "-o", out]
        cmds = [cmd(sr, outs[0])] + ([cmd(base, outs[1])] if base else [])
        measured = measure_in_turns(cmds, RUNS, 1)
        _, peak = measure(cmd(sr, outs[0]), runs=1, warmup=0)
        (whole, phases) = measured[0]
        row = f"| {size} | {1024 * 768 / side ** 2:.1%} | {phases['render']:.3f} | {whole:.3f} | {peak / 1024:.0f} |"
        if base:
            b_whole, b_phases = measured[1]
            if open(outs[0], "rb").read() != open(outs[1], "rb").read():
                raise SystemExit(f"large_frame.py: {size}: the builds' PNGs differ")
            row += f" {b_phases['render']:.3f} | {b_whole:.3f} | {phases['render'] / b_phases['render']:.2f} |"
        if side <= LLVMPIPE_MAX:
            srb.W = srb.H = side
            mvp = srb.ortho(0, side, 0, side, -1, 1)
            png = os.path.join(work, f"frame-{side}-msaa4.png")
            srb.llvmpipe(ctx, tris, mvp, 4, png)
            gl = statistics.median([srb.llvmpipe(ctx, tris, mvp, 4, png) for _ in range(RUNS)])
            row += f" {gl:.3f} | {phases['render'] / gl:.2f} |"
        else:
            row += " - | - |"
        print(row, flush=True)


if __name__ == "__main__":
    main()
