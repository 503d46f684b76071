#!/usr/bin/env python3
"""Driver of bench/stream_speed.sh: how fast the stream is read and written
(issue "Performance at scale", item 2), against a baseline build if given.

    stream_speed.py BINDIR WORKDIR [BASELINE_BINDIR]

- Reading: scene-render's read phase (--timings: parse, build the scene,
  project) on seeded random triangles (bench/random_triangles.py, 100k and
  1M) and on polyfill3's streams of demo 2's faces at incr 0.5 and 0.25, at a
  16x12 frame for the triangles (nothing to render) and 1024x768 for demo 2;
  MB/s of NDJSON read. Median of 5 after a warm-up, the builds taking turns.
  The peer: `jq empty` (jq parsing every value and printing nothing), whole
  process, median of 3 after a warm-up, and the ratio of each build's read
  phase to it.
- Writing: polyfill3 alone, output discarded (bench/timing.py); MB/s written.
- The pipeline `polyfill3 | scene-render`, `polyfill3 --merge |
  scene-render` (runs of a row), `polyfill3 --merge=blocks | scene-render`
  (rectangles of runs), and `polyfill3 --merge VIEW --cull=none |
  scene-render` (only the cells in view written), against scene-render
  texturing the same faces directly (bench/timing.py, whole process, every
  build's commands taking turns, median of 5), and the ratios; the images
  must be byte for byte the same.
"""
import math
import os
import shutil
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from timing import measure, measure_in_turns  # noqa: E402

VIEW = ["--perspective", "55,1,0,1000", "--lookat", "0,100,-5,0,0,-900"]


def read_phases(srs, args, runs=5):
    """The median read phase (--timings) of each scene-render in `srs` on
    `args`, over `runs` rounds after a warm-up, the builds taking turns
    (bench/timing.py's `measure_in_turns`)."""
    cmds = [[sr, "--timings"] + args for sr in srs]
    return [phases["read"] for _, phases in measure_in_turns(cmds, runs)]


def main():
    bindir, work = sys.argv[1], sys.argv[2]
    base = sys.argv[3] if len(sys.argv) > 3 else None
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    here = os.path.join(root, "bench")
    builds = [("this build", bindir)] + ([("baseline", base)] if base else [])
    inputs = []
    for n in (100_000, 1_000_000):
        path = os.path.join(work, f"tri-{n}.ndjson")
        if not os.path.exists(path):
            with open(path, "w") as fh:
                subprocess.run([sys.executable, os.path.join(here, "random_triangles.py"), str(n), "auto"],
                               stdout=fh, check=True)
        inputs.append((f"{n} random triangles", path, ["--size", "16x12", "--aa", "none"]))
    faces = open(os.path.join(root, "fixtures/scenes/demo2-faces.json")).read()
    faces = faces.replace('"../patterns/', '"%s/fixtures/patterns/' % root)
    scenes = {}
    for incr in ("0.5", "0.25"):
        scene = os.path.join(work, f"faces-{incr}.json")
        open(scene, "w").write(faces.replace('"incr":2', '"incr":%s' % incr))
        stream = os.path.join(work, f"p3-{incr}.ndjson")
        with open(stream, "w") as fh:
            subprocess.run([os.path.join(bindir, "polyfill3"), scene], stdout=fh, check=True)
        scenes[incr] = (scene, stream)
        inputs.append((f"polyfill3 stream, demo 2 faces, incr {incr}", stream, ["--size", "1024x768"] + VIEW))
    jq = shutil.which("jq")
    cols = " | ".join(f"{b} s | {b} MB/s" for b, _ in builds)
    peer = " | jq empty s | jq MB/s | " + " | ".join(f"{b}/jq" for b, _ in builds) if jq else ""
    print(f"| reading (scene-render read phase) | MB | {cols}{peer} |")
    print("|---|---:|" + "---:|---:|" * len(builds) + ("---:|---:|" + "---:|" * len(builds) if jq else ""))
    read_times = {}
    for name, path, args in inputs:
        mb = os.path.getsize(path) / 1e6
        cells = []
        srs = [os.path.join(d, "scene-render") for _, d in builds]
        ts = read_phases(srs, args + [path, "-o", os.path.join(work, "out.png")])
        for (b, _), t in zip(builds, ts):
            read_times[(name, b)] = (mb, t)
            cells.append(f"{t:.3f} | {mb / t:.0f}")
        if jq:
            tj, _ = measure([jq, "empty", path], runs=3)
            cells.append(f"{tj:.3f} | {mb / tj:.0f}")
            cells += [f"{t / tj:.2f}" for t in ts]
        print(f"| {name} | {mb:.0f} | " + " | ".join(cells) + " |")
    print()
    for b, _ in builds:
        # Time against size, between the two sizes of each kind of input.
        pairs = [("100000 random triangles", "1000000 random triangles"),
                 ("polyfill3 stream, demo 2 faces, incr 0.5", "polyfill3 stream, demo 2 faces, incr 0.25")]
        fits = []
        for small, large in pairs:
            (m0, t0), (m1, t1) = read_times[(small, b)], read_times[(large, b)]
            fits.append(f"{small.split(',')[0].replace('100000 ', '')}: N^{math.log(t1 / t0) / math.log(m1 / m0):.2f}")
        print(f"- {b}, reading time against stream size: " + "; ".join(fits) + ".")
    print()
    print(f"| writing (polyfill3, output discarded) | MB | {cols} |")
    print("|---|---:|" + "---:|---:|" * len(builds))
    write_times = {}
    for incr, (scene, stream) in scenes.items():
        mb = os.path.getsize(stream) / 1e6
        cells = []
        for b, d in builds:
            t, _ = measure([os.path.join(d, "polyfill3"), scene], runs=3)
            write_times[(incr, b)] = (mb, t)
            cells.append(f"{t:.3f} | {mb / t:.0f}")
        print(f"| demo 2 faces, incr {incr} | {mb:.0f} | " + " | ".join(cells) + " |")
    print()
    for b, _ in builds:
        (m0, t0), (m1, t1) = write_times[("0.5", b)], write_times[("0.25", b)]
        print(f"- {b}, writing time against output size: N^{math.log(t1 / t0) / math.log(m1 / m0):.2f}.")
    print()
    cols = " | ".join(f"{b}: pipe s | --merge s | --merge=blocks s | --merge --cull=none s | direct s | "
                      "pipe/direct | --merge/direct | --merge=blocks/direct | --merge --cull=none/direct"
                      for b, _ in builds)
    print(f"| pipeline, 1024x768 --aa exact | {cols} |")
    print("|---|" + "---:|" * 9 * len(builds))
    # polyfill3 takes scene-render's camera flags: the same view.
    cull = " ".join(["--merge"] + VIEW + ["--cull=none"])
    for incr, (scene, _) in scenes.items():
        # Every build's commands take turns in one measurement, so that a
        # slow spell of the machine falls on all of them alike.
        plan, cmds = [], []
        for k, (b, d) in enumerate(builds):
            p3, sr = os.path.join(d, "polyfill3"), os.path.join(d, "scene-render")
            # A build from before polyfill3's --cull=FACES cannot leave out only
            # what is off view: its row has no such column.
            # Nor can one from before --merge=blocks join rows.
            usage = subprocess.run([p3, "--help"], capture_output=True, text=True).stdout
            names = ["pipe", "merge"] + (["blocks"] if "--merge[=" in usage else []) \
                + (["cull"] if "--cull[=" in usage else []) + ["direct"]
            outs = {name: os.path.join(work, f"{name}-{k}.png") for name in names}
            render = f"'{sr}' --size 1024x768 {' '.join(VIEW)} -"
            piped = {"pipe": "", "merge": "--merge", "blocks": "--merge=blocks", "cull": cull}
            cmds += [["sh", "-c", f"'{p3}' {piped[n]} '{scene}' | {render} -o '{outs[n]}'"]
                     if n != "direct" else [sr, "--size", "1024x768"] + VIEW + [scene, "-o", outs[n]]
                     for n in names]
            plan.append((b, names, outs))
        measured = iter(t for t, _ in measure_in_turns(cmds, runs=5))
        cells = []
        for b, names, outs in plan:
            times = {n: next(measured) for n in names}
            images = {n: open(o, "rb").read() for n, o in outs.items()}
            if any(images[n] != images["direct"] for n in names):
                raise SystemExit(f"stream_speed.py: {b}, incr {incr}: the images differ")
            direct = times["direct"]
            row = [f"{times[n]:.3f}" if n in times else "-" for n in ("pipe", "merge", "blocks", "cull", "direct")]
            row += [f"{times[n] / direct:.1f}" if n in times else "-" for n in ("pipe", "merge", "blocks", "cull")]
            cells.append(" | ".join(row))
        print(f"| demo 2 faces, incr {incr} | " + " | ".join(cells) + " |")
    print()
    print("The images of each row are byte for byte the same (checked by this script).")
    print()
    # What each pipeline sends through the pipe, from this build.
    p3 = os.path.join(bindir, "polyfill3")
    print("| stream sent through the pipe (this build) | plain MB | records | --merge MB | records "
          "| --merge=blocks MB | records | --merge --cull=none MB | records |")
    print("|---|" + "---:|" * 8)
    for incr, (scene, _) in scenes.items():
        cells = []
        for flags in ([], ["--merge"], ["--merge=blocks"], cull.split()):
            out = subprocess.run([p3] + flags + [scene], capture_output=True, check=True).stdout
            records = out.count(b"\n")
            cells.append(f"{len(out) / 1e6:.1f} | {records:,}")
        print(f"| demo 2 faces, incr {incr} | " + " | ".join(cells) + " |")


if __name__ == "__main__":
    main()
