#!/usr/bin/env python3
"""Driver of bench/clip_bound.sh: how much of llvmpipe MSAA 4x's render time
is left for exact visibility once a soup's triangles are cut into their pixel
fragments by a plain f64 clipper (bench/clip_bound.rs), on the scenes of
bench/aa_scaling.sh.

    clip_bound.py CLIP_BOUND WORKDIR [N ...]

For each set in AA_SETS (default `auto s20`) and N: the bound's fragments and
its clipping time on one thread (median of AA_RUNS, default 3), half of it
(two cores, perfectly shared), llvmpipe MSAA 4x's render (as aa_scaling.py
times it: median of AA_RUNS after a warm-up), and what that render time
leaves of two cores' time per fragment for everything else: binning,
ordering, visibility and the pixel's colour ((2 x MSAA 4x - clip) /
fragments, in nanoseconds of one core).

Every fragment is cut here; a renderer that drops fragments lying behind a
covered pixel before cutting them (as --aa exact does) cuts fewer, so in
deep scenes (`s20` at 100,000 and more) this is no bound on it.
"""
import os
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from aa_scaling import RUNS, W, H, arguments, llvmpipe_view, msaa4_render, scene  # noqa: E402


def main():
    bound, work, ns = arguments()
    gl_view = llvmpipe_view()
    print("| set | N | fragments | full-pixel | clip, 1 thread (s) | clip/2 (s) | MSAA 4x render (s) "
          "| (clip/2)/MSAA4x | CPU ns a fragment left |")
    print("|---|---:|---:|---:|---:|---:|---:|---:|---:|")
    for name in os.environ.get("AA_SETS", "auto s20").split():
        for n in ns:
            path = scene(work, name, n)
            out = subprocess.run([bound, path, str(W), str(H), str(RUNS)], capture_output=True, text=True,
                                 check=True).stdout.split()
            frags, full, clip = int(out[1]), int(out[2]), float(out[4])
            gl = msaa4_render(gl_view, path, os.path.join(work, f"tri-{name}-{n}-msaa4.png"))
            left = (2 * gl - clip) / frags * 1e9
            print(f"| {name} | {n} | {frags} | {full} | {clip:.3f} | {clip / 2:.3f} | {gl:.3f} "
                  f"| {clip / 2 / gl:.2f} | {left:.0f} |", flush=True)


if __name__ == "__main__":
    main()
