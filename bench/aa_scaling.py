#!/usr/bin/env python3
"""Driver of bench/aa_scaling.sh: exact anti-aliasing against Mesa's llvmpipe
MSAA 4x as the triangle count grows (issue "Performance at scale", item 1).

    aa_scaling.py SCENE_RENDER WORKDIR [N ...]

Scenes, seeded, 1024x768, N flat triangles, in three sets: from
bench/random_triangles.py, a soup of random triangles, `auto` (vertex spread
s = sqrt(4WH / 0.3N), about four layers a pixel at every N) and `s20` (s = 20
px, so the depth grows with N); from bench/layered_mesh.py, `mesh`: four
sheets of N/4 triangles each over the frame, triangles sharing their edges
within a sheet, sheets crossing along curves (about four layers a pixel, as
`auto`). AA_SETS (default `auto s20 mesh`) picks the sets.
For each: scene-render --aa exact (render-phase time from --timings, and the
whole process; median of AA_RUNS, default 3, after a warm-up; one run from a
million triangles up), scene-render --aa ss4 (render phase, taking turns with
exact: the point-sampled choice a user has on such scenes) and llvmpipe MSAA
4x (upload, draw, resolve, read back; median of AA_RUNS after a warm-up).
Prints a Markdown table with ratios, and the fitted exponent of time against
N (least squares on log-log) for each set and renderer.
"""
import math
import os
import statistics
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import scene_render_bench as srb  # noqa: E402
from timing import measure_in_turns  # noqa: E402

# Runs per measurement (median); scenes of a million triangles take minutes
# under --aa exact, so they get one run and no warm-up.
RUNS = int(os.environ.get("AA_RUNS", "3"))
HEAVY = 1_000_000

W, H = 1024, 768


def scene_render(sr, path, out, runs, warmup):
    """(median render-phase s, median whole-process s) of --aa exact, and the
    median render-phase s of --aa ss4, the two taking turns."""
    def cmd(aa, to):
        return [sr, "--size", f"{W}x{H}", "--background", "20,20,80", "--aa", aa, "--timings", path, "-o", to]
    ss4_out = out.replace(".png", "-ss4.png")
    (whole, phases), (_, ss4) = measure_in_turns([cmd("exact", out), cmd("ss4", ss4_out)], runs, warmup)
    return phases["render"], whole, ss4["render"]


GENERATORS = {
    "auto": ["random_triangles.py", "auto"],
    "s20": ["random_triangles.py", "20"],
    "mesh": ["layered_mesh.py"],
}


def scene(work, name, n):
    """The path of set `name`'s scene of `n` triangles in `work`, generated
    (seeded) the first time it is asked for."""
    path = os.path.join(work, f"tri-{name}-{n}.ndjson")
    if not os.path.exists(path):
        script, *args = GENERATORS[name]
        here = os.path.dirname(os.path.abspath(__file__))
        with open(path + ".tmp", "w") as fh:
            subprocess.run([sys.executable, os.path.join(here, script), str(n), *args], stdout=fh, check=True)
        os.replace(path + ".tmp", path)
    return path


def arguments():
    """The program and work directory of the command line, and its N
    (default 10,000, 100,000, 200,000 and a million)."""
    return sys.argv[1], sys.argv[2], [int(n) for n in sys.argv[3:]] or [10_000, 100_000, 200_000, 1_000_000]


def llvmpipe_view():
    """llvmpipe's context and the W x H frame's 2D projection."""
    import moderngl
    return moderngl.create_standalone_context(backend="egl"), srb.ortho(0, W, 0, H, -1, 1)


def msaa4_render(gl_view, path, png):
    """llvmpipe MSAA 4x's render time of the scene at `path` (median of RUNS
    after a warm-up), its image written to `png`."""
    ctx, mvp = gl_view
    tris = srb.load_triangles(path)
    srb.llvmpipe(ctx, tris, mvp, 4, png)
    return statistics.median([srb.llvmpipe(ctx, tris, mvp, 4, png) for _ in range(RUNS)])


def fit(ns, ts):
    xs, ys = [math.log(n) for n in ns], [math.log(t) for t in ts]
    mx, my = sum(xs) / len(xs), sum(ys) / len(ys)
    return sum((x - mx) * (y - my) for x, y in zip(xs, ys)) / sum((x - mx) ** 2 for x in xs)


def main():
    sr, work, ns = arguments()
    gl_view = llvmpipe_view()
    print("| set | N | exact render (s) | exact whole (s) | ss4 render (s) | MSAA 4x render (s) "
          "| exact/MSAA4x render | ss4/MSAA4x render |")
    print("|---|---:|---:|---:|---:|---:|---:|---:|")
    fits = []
    for name in os.environ.get("AA_SETS", "auto s20 mesh").split():
        ex, s4, gl = [], [], []
        for n in ns:
            path = scene(work, name, n)
            runs, warmup = (1, 0) if n >= HEAVY else (RUNS, 1)
            render, whole, ss4 = scene_render(sr, path, os.path.join(work, f"tri-{name}-{n}.png"), runs, warmup)
            t_gl = msaa4_render(gl_view, path, os.path.join(work, f"tri-{name}-{n}-msaa4.png"))
            ex.append(render)
            s4.append(ss4)
            gl.append(t_gl)
            print(f"| {name} | {n} | {render:.3f} | {whole:.3f} | {ss4:.3f} | {t_gl:.3f} "
                  f"| {render / t_gl:.2f} | {ss4 / t_gl:.2f} |", flush=True)
        if len(set(ns)) > 1:
            fits.append((name, fit(ns, ex), fit(ns, s4), fit(ns, gl)))
    print()
    for name, e, s, g in fits:
        print(f"- {name}: time ~ N^{e:.2f} (exact render), N^{s:.2f} (ss4 render), N^{g:.2f} (llvmpipe MSAA 4x), "
              "fitted over N = " + ", ".join(str(n) for n in ns) + ".")


if __name__ == "__main__":
    main()
