#!/usr/bin/env python3
"""Driver of bench/same_images.sh: this build's images against a baseline
build's, scene by scene, for a change meant to alter speed and nothing else.

    same_images.py BINDIR BASELINE_BINDIR WORKDIR

Each scene is rendered by both builds' scene-render (default `--aa exact`)
to an 8-bit PNG and to a PFM (32-bit float, linear light). The table says
whether the PNGs are byte for byte the same, and the largest difference
between the PFMs (0 when they are the same file), with one whole-process
time each (a guide, not a benchmark: one run, no warm-up).

Scenes: the texture benchmark's (bench/texbench.py), the fixtures' spheres,
lit and photographed globes and house, demo 2 over its background pattern
(the golden test's), and the random flat triangles of bench/aa_scaling.sh at
10,000 to 200,000, about 4 layers a pixel (`auto`) and 20-pixel triangles
(`s20`), one of them over a transparent background, and its layered meshes
(`mesh`, bench/layered_mesh.py) at the same counts.
"""
import array
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
sys.path.insert(0, HERE)
import aa_scaling  # noqa: E402
import texbench  # noqa: E402
from timing import run_once  # noqa: E402


def read_pfm(path):
    """The floats of a PFM (little-endian, as scene-render writes it)."""
    with open(path, "rb") as fh:
        data = fh.read()
    # Three header lines: "PF", "W H", the scale (negative: little-endian).
    at = 0
    for _ in range(3):
        at = data.index(b"\n", at) + 1
    values = array.array("f")
    values.frombytes(data[at:])
    if sys.byteorder != "little":
        values.byteswap()
    return values


def render(sr, args, out):
    """Seconds of one whole-process run of `sr args -o out` (bench/timing.py)."""
    return run_once([sr] + args + ["-o", out])[0]


def scenes(work):
    """(name, scene-render arguments) of every scene compared."""
    out = []
    for name, (path, size, cam) in texbench.scenes(
        work, ["plane", "wall", "demo2", "demo1", "tiles", "photo-plane", "photo-sphere"]
    ).items():
        out.append((name, cam + ["--size", size, path]))
    fix = os.path.join(ROOT, "fixtures", "scenes")
    ortho = ["--ortho", "-80,80,-60,60,0,100", "--size", "800x600"]
    for name in ("two-spheres", "earth-lit", "earth-photo"):
        out.append((name, ortho + [os.path.join(fix, f"{name}.json")]))
    out.append(("house", ["--perspective", "40,auto,1,500", "--lookat", "30,25,60,0,10,0",
                          "--size", "480x360", os.path.join(fix, "house.json")]))
    out.append(("demo2 over bkgrnd.pat", [
        "--perspective", "55,1,0,1000", "--lookat", "0,100,-5,0,0,-900", "--cull", "back",
        "--background-pattern", os.path.join(ROOT, "fixtures", "patterns", "bkgrnd.pat"),
        "--size", "1024x768", os.path.join(ROOT, "examples", "scenes", "demo2.json")]))
    for kind in ("auto", "s20", "mesh"):
        for n in (10_000, 100_000, 200_000):
            out.append((f"{n} triangles, {kind}", ["--size", "1024x768", aa_scaling.scene(work, kind, n)]))
    out.append(("10000 triangles, auto, --background none",
                ["--size", "1024x768", "--background", "none",
                 os.path.join(work, "tri-auto-10000.ndjson")]))
    return out


def main():
    bindir, basedir, work = sys.argv[1:4]
    new = os.path.join(bindir, "scene-render")
    old = os.path.join(basedir, "scene-render")
    print("| scene | this build s | baseline s | 8-bit PNG | PFM, largest difference |")
    print("|---|---:|---:|---|---:|")
    same = 0
    listed = scenes(work)
    for name, args in listed:
        png = [os.path.join(work, f"{who}.png") for who in ("new", "old")]
        pfm = [os.path.join(work, f"{who}.pfm") for who in ("new", "old")]
        t_new = render(new, args, png[0])
        t_old = render(old, args, png[1])
        with open(png[0], "rb") as a, open(png[1], "rb") as b:
            png_same = a.read() == b.read()
        same += png_same
        if "none" in args:
            diff = "(no PFM with alpha)"
        else:
            render(new, args, pfm[0])
            render(old, args, pfm[1])
            fa, fb = read_pfm(pfm[0]), read_pfm(pfm[1])
            d = max((abs(x - y) for x, y in zip(fa, fb)), default=0.0) if len(fa) == len(fb) else float("inf")
            diff = f"{d:.3g}"
        print(f"| {name} | {t_new:.2f} | {t_old:.2f} | {'same' if png_same else 'DIFFERENT'} | {diff} |")
    print()
    print(f"8-bit images byte for byte the same: {same} of {len(listed)}.")


if __name__ == "__main__":
    main()
