#!/usr/bin/env bash
# pat-tile against ImageMagick (`convert -size WxH tile:in.png`) and netpbm
# (`pnmtile W H`): a 64x64 pattern tiled to 4096x4096, PNG and PPM output.
# Prints one markdown table: median wall time of each command (bench/timing.py),
# its ratio to pat-tile for the same format, and the output size. It also
# checks that the three tools produce the same pixels.
# Not run in CI. Usage: bench/pat_tile.sh [RUNS]
set -euo pipefail
cd "$(dirname "$0")/.."
runs=${1:-7}
size=4096

need() { command -v "$1" >/dev/null 2>&1; }
# The real ImageMagick: /usr/local/bin/convert may be a stand-in on these machines.
im=/usr/bin/convert-im6.q16
if [ ! -x "$im" ] || ! need pnmtile || ! need pnmtopng; then
  apt-get update -qq
  DEBIAN_FRONTEND=noninteractive apt-get install -y -qq imagemagick netpbm >/dev/null
fi
cargo build --release --quiet --bins
bin=$PWD/target/release

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
pat=fixtures/patterns/brick.pat
"$bin/pat-tile" --size 64x64 -o "$work/in.png" "$pat"
"$bin/pat-tile" --size 64x64 -o "$work/in.ppm" "$pat"

cd "$work"
# policy.xml of Debian's ImageMagick may cap the pixel cache; 4096^2 fits the default.
declare -a names cmds
add() { names+=("$1"); cmds+=("$2"); }
add "pat-tile png"      "$bin/pat-tile --size ${size}x${size} -o ours.png $OLDPWD/$pat"
add "imagemagick png"   "$im -size ${size}x${size} tile:in.png im.png"
add "netpbm png"        "sh -c 'pnmtile $size $size in.ppm | pnmtopng > nb.png'"
add "pat-tile ppm"      "$bin/pat-tile --size ${size}x${size} -o ours.ppm $OLDPWD/$pat"
add "imagemagick ppm"   "$im -size ${size}x${size} tile:in.png -depth 8 im.ppm"
add "netpbm ppm"        "sh -c 'pnmtile $size $size in.ppm > nb.ppm'"

# Median of $runs after a warm-up, the six taking turns (bench/timing.py).
python3 - "$runs" "$OLDPWD/bench" "${cmds[@]}" <<'PY' > times.txt
import shlex, sys
sys.path.insert(0, sys.argv[2])
from timing import measure_in_turns
for wall, _ in measure_in_turns([shlex.split(c) for c in sys.argv[3:]], int(sys.argv[1])):
    print(wall)
PY

# Same pixels from every route (all three anchor the pattern so that 4096 = 64k
# rows end on the pattern's bottom row; PPM files are compared after the header).
same() { cmp -s <(tail -c +16 "$1") <(tail -c +16 "$2") && echo yes || echo NO; }
$im im.png im_png.ppm; pngtopnm nb.png > nb_png.ppm; pngtopnm ours.png > ours_png.ppm
pixels_im=$(same ours.ppm im.ppm); pixels_nb=$(same ours.ppm nb.ppm)
pixels_png=$( [ "$(same ours_png.ppm im_png.ppm)" = yes ] && [ "$(same ours_png.ppm nb_png.ppm)" = yes ] && echo yes || echo NO)

python3 - "$runs" <<PY
import os, sys
names = """$(printf '%s\n' "${names[@]}")""".strip().split("\n")
files = ["ours.png", "im.png", "nb.png", "ours.ppm", "im.ppm", "nb.ppm"]
med = [float(t) for t in open("times.txt")]
print(f"pat-tile: 64x64 brick.pat -> ${size}x${size}, median of {sys.argv[1]} runs after a warm-up, "
      "the commands taking turns (bench/timing.py)")
print()
print("| command | median s | vs pat-tile (same format) | output MiB |")
print("|---|---:|---:|---:|")
for i, n in enumerate(names):
    ours = med[0] if "png" in n else med[3]
    print(f"| {n} | {med[i]:.3f} | {med[i]/ours:.1f}x | {os.path.getsize(files[i])/2**20:.1f} |")
print()
print("same pixels: ppm vs imagemagick: $pixels_im, ppm vs netpbm: $pixels_nb, png all three: $pixels_png")
PY
echo
echo "machine: $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //'), $(date -u +%Y-%m-%d)"
echo "versions: $($im -version | head -1 | cut -d' ' -f2-3), netpbm $(dpkg-query -W -f='${Version}' netpbm 2>/dev/null)"
