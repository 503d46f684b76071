"""What each of scene-render's work-saving skips saves (issue 7): per skip, a
scene where it matters, rendered with the skip and without it
(`--no-skip NAME`), the median of RUNS render phases (`--timings`) after a
warm-up, with one thread, the two taking turns (bench/timing.py), and whether the two PNGs are byte-identical. The referenced-patterns
skip has no switch: a stream referencing 1 of 200 pattern files in its
directory is compared with one referencing all 200 (read phase and whole
process).

    python3 bench/skips.py TARGET/release WORK > bench/RESULTS-skips.md

Standard library only (and bench/timing.py). Driven by bench/skips.sh.
"""

import json
import os
import platform
import shutil
import subprocess
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from timing import measure_in_turns  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
RUNS = 5

# Side of the large patterns: the MIP scene's (its pyramid is what the lazy
# build saves) and the referenced-patterns scene's 200 files (large enough
# that reading one takes visible time, small enough that 200 decoded copies,
# 32 bytes a texel, stay near 400 MB).
MIP_SIDE = 1024
REFERENCED_SIDE = 256
REFERENCED_FILES = 200


def write_pat(path, size, colors, index):
    """A pattern file (docs/pat-format.md): `SIZE NCOLORS`, then per colour its RGB and
    one row of 16-bit hex words per texel row; `index(c, r)` is a texel's
    colour or None (transparent)."""
    out = [f"{size} {len(colors)}\n"]
    rows = [[index(c, r) for c in range(size)] for r in range(size)]
    for ci, rgb in enumerate(colors):
        out.append(" ".join(map(str, rgb)) + "\n")
        for row in rows:
            words = []
            for w in range(0, size, 16):
                bits = 0
                for c in range(w, w + 16):
                    bits = (bits << 1) | (row[c] == ci)
                words.append("%04x" % bits)
            out.append(" ".join(words) + "\n")
    with open(path, "w") as fh:
        fh.write("".join(out))


def write_json(path, records):
    with open(path, "w") as fh:
        for r in records:
            fh.write(json.dumps(r) + "\n")


def wall(z, pattern, incr, half=(8, 6), rotate=7, color=(128, 128, 128)):
    w, h = half
    return {"vertices": [[-w, -h, z - 1.5], [w, -h, z + 1.5], [w, h, z + 1.5], [-w, h, z - 1.5]],
            "color": list(color), "pattern": {"file": pattern, "incr": incr, "rotate": rotate}}


def scenes(work):
    """name -> (what the skip saves, scene file, size, flags, no-skip name)."""
    # A 16x16 opaque checker of single texels, and sparse dots: one opaque
    # texel in every 8x8 block (1/64 of the texels), the rest transparent.
    write_pat(os.path.join(work, "checker.pat"), 16, [(230, 230, 230), (20, 20, 120)],
              lambda c, r: (c + r) % 2)
    write_pat(os.path.join(work, "dots.pat"), 16, [(240, 40, 40)],
              lambda c, r: 0 if c % 8 == 0 and r % 8 == 0 else None)
    big = os.path.join(work, "big.pat")
    if not os.path.exists(big):
        write_pat(big, MIP_SIDE, [(230, 230, 230), (20, 20, 120), (200, 120, 20)],
                  lambda c, r: (c // 3 + r // 5) % 3)
    wide = ["--perspective", "60,1.333,0.5,1000", "--lookat", "0,2,0,0,1.2,-20"]
    head_on = ["--perspective", "60,1.333,0.5,100", "--lookat", "0,0,0,0,0,-10"]
    # hidden: a receding checker floor (minified towards the horizon, EWA's
    # costly case) wholly behind an opaque textured wall filling the view.
    write_json(os.path.join(work, "hidden.json"), [
        {"vertices": [[-200, 0, -1], [200, 0, -1], [200, 0, -401], [-200, 0, -401]],
         "color": [128, 128, 128], "pattern": {"file": "checker.pat", "incr": 1}},
        {"vertices": [[-50, -50, -0.9], [50, -50, -0.9], [50, 50, -0.9], [-50, 50, -0.9]],
         "color": [128, 128, 128], "pattern": {"file": "checker.pat", "incr": 0.05}},
    ])
    # mip: a 1024-texel pattern on a close-up wall, only magnified.
    write_json(os.path.join(work, "mip.json"), [wall(-10, "big.pat", 0.1)])
    # transparent: sparse dots on the receding plane.
    write_json(os.path.join(work, "transparent.json"), [
        {"vertices": [[-200, 0, -1], [200, 0, -1], [200, 0, -401], [-200, 0, -401]],
         "color": [128, 128, 128], "pattern": {"file": "dots.pat", "incr": 1}}])
    # magnify: the close-up checker wall (each texel ~40 pixels across).
    write_json(os.path.join(work, "magnify.json"), [wall(-10, "checker.pat", 1)])
    return [
        ("hidden", "hidden pixels not filtered (EWA, exact)", "hidden.json", "640x480",
         wide + ["--aa", "exact", "--filter", "ewa"]),
        ("hidden", "hidden samples not textured (trilinear, ss16)", "hidden.json", "320x240",
         wide + ["--aa", "ss16", "--filter", "trilinear"]),
        ("hidden", "hidden fragments not made (box, exact)", "hidden.json", "640x480",
         wide + ["--aa", "exact"]),
        ("mip", "MIP levels built only when minified (trilinear, exact)", "mip.json", "320x240",
         head_on + ["--aa", "exact", "--filter", "trilinear"]),
        ("transparent", "transparent runs skipped (box, exact)", "transparent.json", "640x480",
         wide + ["--aa", "exact"]),
        ("magnify", "single-cell fragments whole (box, exact)", "magnify.json", "640x480",
         head_on + ["--aa", "exact"]),
    ]


def referenced_scenes(work):
    """Two streams of the same 200 tiles over a directory of 200 pattern
    files (copies of one, so the images are the same): one references only
    the first file, the other all 200."""
    d = os.path.join(work, "referenced")
    os.makedirs(d, exist_ok=True)
    first = os.path.join(d, "p000.pat")
    if not os.path.exists(first):
        write_pat(first, REFERENCED_SIDE, [(230, 230, 230), (20, 20, 120), (200, 120, 20)],
                  lambda c, r: (c // 3 + r // 5) % 3)
    for i in range(1, REFERENCED_FILES):
        p = os.path.join(d, "p%03d.pat" % i)
        if not os.path.exists(p):
            shutil.copyfile(first, p)

    def tiles(name):
        recs = []
        for i in range(REFERENCED_FILES):
            x, y = i % 20, i // 20
            recs.append({"vertices": [[x, y, 0], [x + 1, y, 0], [x + 1, y + 1, 0], [x, y + 1, 0]],
                         "color": [128, 128, 128], "pattern": {"file": name(i), "incr": 1 / 16}})
        return recs

    one = os.path.join(d, "one.json")
    write_json(one, tiles(lambda i: "p000.pat"))
    every = os.path.join(d, "all.json")
    write_json(every, tiles(lambda i: "p%03d.pat" % i))
    return one, every


NOTES = """Notes:

- hidden: a checker floor receding to the horizon lies wholly behind an opaque textured wall
  that fills the view. With the skip its fragments are never filtered (`--aa exact`: a deferred
  colour filtered only once visible; `--aa ss<N>`: the depth test first, texturing only the
  samples that stay). Without it every covered fragment or sample is filtered. With the box
  filter (exact) the skip is the tile sweep's drop: a textured fragment behind everything that
  covers its pixel is not made (nor clipped to its pixel). Without the skip it is made, swept and
  found hidden; since 2026-11-27 (4b1bbc6) it is not cut into texel cells either way (a fragment
  over several cells is cut only where it shows), so this row saves less than it did (2.89x on
  2026-11-21, 1.2-1.4x now; whole process at 640x480 under callgrind: 484 against 566 million
  instructions).
- mip: a 1024x1024 pattern on a wall that is magnified everywhere: with the skip no pixel asks
  for a MIP level, so the pyramid is never built; without it the pattern's pyramid is built
  before rendering (what an eager loader would do). The ratio is the pyramid's cost.
- transparent: a 16x16 pattern with one opaque texel per 8x8 block (1/64) on a plane receding
  to the horizon, where a pixel spans up to hundreds of texels: the cut skips strips whose
  texel row has no opaque texel in the fragment's columns, unclipped, and visits only opaque
  runs.
- magnify: a 16x12-texel checker wall seen from 8 units, each texel ~40 pixels across: nearly
  every fragment lies in one cell and is taken whole instead of clipped against the cell's
  four sides.
- referenced patterns: the same scene (200 tiles) either way, the patterns are copies of one
  file; 'read' is the whole read phase (parsing the stream, reading and decoding the
  patterns). The render phase is not what this skip changes.
"""


def run(sr, cases):
    """For each case (scene, size, flags, out): (read s, render s, whole s),
    medians of RUNS rounds after a warm-up, the cases taking turns
    (bench/timing.py); each PNG is left in its `out`."""
    cmds = [[sr, "--size", size, "--threads", "1", "--timings", *flags, scene, "-o", out]
            for scene, size, flags, out in cases]
    return [(ph["read"], ph["render"], whole) for whole, ph in measure_in_turns(cmds, RUNS)]


def same(a, b):
    with open(a, "rb") as fa, open(b, "rb") as fb:
        return fa.read() == fb.read()


def header():
    cpu = next((l.split(":", 1)[1].strip() for l in open("/proc/cpuinfo")
                if l.startswith("model name")), "?")
    load = " ".join(open("/proc/loadavg").read().split()[:3])
    commit = subprocess.run(["git", "-C", ROOT, "rev-parse", "--short", "HEAD"],
                            capture_output=True, text=True).stdout.strip()
    dirty = subprocess.run(["git", "-C", ROOT, "status", "--porcelain", "--untracked-files=no"],
                           capture_output=True, text=True).stdout.strip()
    print("# What each skip saves (issue 7)")
    print()
    print(f"Run {time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())} on {platform.system()} "
          f"{platform.machine()}, {os.cpu_count()} cores ({cpu}), load average {load} at the start.")
    print(f"Commit {commit}{' (with uncommitted changes)' if dirty else ''}. The machine is shared "
          "with other jobs (load above its 2 cores): compare the ratios, measured in the same run, "
          "rather than times across runs.")
    print(f"Times: median of {RUNS} runs after a warm-up, with and without taking turns "
          "(bench/timing.py), `scene-render --threads 1 --timings`' render phase; "
          "'without' is `--no-skip NAME` (a hidden flag, for this benchmark). 'identical' compares "
          "the two PNGs byte for byte.")
    print()


def main():
    bins, work = sys.argv[1], sys.argv[2]
    sr = os.path.join(bins, "scene-render")
    header()
    print("| skip | scene | render s with | render s without | without / with | identical |")
    print("|---|---|---:|---:|---:|---|")
    for name, what, scene, size, flags in scenes(work):
        scene = os.path.join(work, scene)
        a, b = os.path.join(work, f"{name}-with.png"), os.path.join(work, f"{name}-without.png")
        w, wo = run(sr, [(scene, size, flags, a), (scene, size, flags + ["--no-skip", name], b)])
        flagtext = " ".join(flags[4:])
        print(f"| {name} | {what}: {os.path.basename(scene)} {size} `{flagtext}` | {w[1]:.4f} | "
              f"{wo[1]:.4f} | {wo[1] / w[1]:.2f} | {'yes' if same(a, b) else 'NO'} |")
    print()
    one, every = referenced_scenes(work)
    a, b = os.path.join(work, "referenced-one.png"), os.path.join(work, "referenced-all.png")
    cam = ["--ortho2", "0,20,0,10"]
    w, wo = run(sr, [(one, "640x320", cam, a), (every, "640x320", cam, b)])
    print(f"Referenced patterns: {REFERENCED_FILES} tiles over a directory of {REFERENCED_FILES} "
          f"{REFERENCED_SIDE}x{REFERENCED_SIDE} pattern files "
          f"({os.path.getsize(os.path.join(os.path.dirname(one), 'p000.pat')) // 1024} KiB each, "
          "copies of one). Only the files a record references are read, each once, so a stream "
          "that references one file reads one; the other stream references all of them. No switch: "
          "the ratio is what reading the unreferenced files would cost.")
    print()
    print("| stream | read s | render s | whole s | identical |")
    print("|---|---:|---:|---:|---|")
    print(f"| references 1 of {REFERENCED_FILES} | {w[0]:.4f} | {w[1]:.4f} | {w[2]:.4f} | |")
    print(f"| references all {REFERENCED_FILES} | {wo[0]:.4f} | {wo[1]:.4f} | {wo[2]:.4f} | "
          f"{'yes' if same(a, b) else 'NO'} |")
    print(f"| all / one | {wo[0] / w[0]:.1f} | {wo[1] / w[1]:.2f} | {wo[2] / w[2]:.1f} | |")
    print()
    print(NOTES)


if __name__ == "__main__":
    main()
