#!/usr/bin/env bash
# Benchmark of pat-from-image's quantizer against pngquant and ImageMagick.
# Not run in CI. Usage: bench/pat_from_image.sh [RUNS]   (RUNS: timing repeats, default 5)
#
# For 10 test images (ImageMagick's built-in photos, drawings and procedural
# images), each resized to 64x64 and 256x256, and K = 4, 8, 16, 32 colours, it
# runs ours (no dithering), `pngquant --nofs K` and `convert +dither -colors K`,
# measures sRGB PSNR, linear-light PSNR and mean OKLab error against the resized
# original (examples/psnr.rs), times each tool (median of RUNS runs, whole
# process: decode, quantize, write), and prints a table with ratios ours/peer.
# Per-case numbers go to bench/out/pat_from_image.csv.
set -euo pipefail

RUNS=${1:-5}
cd "$(dirname "$0")/.."
OUT=bench/out/pat_from_image
mkdir -p "$OUT"

need=()
command -v pngquant >/dev/null || need+=(pngquant)
[ -x /usr/bin/convert ] || need+=(imagemagick)
command -v pnmtopng >/dev/null || need+=(netpbm)
if [ ${#need[@]} -gt 0 ]; then
    apt-get update -qq
    DEBIAN_FRONTEND=noninteractive apt-get install -y -qq "${need[@]}"
fi
IM=/usr/bin/convert

cargo build --release --quiet --bin pat-from-image --example psnr
BIN=${CARGO_TARGET_DIR:-target}/release
OURS=$BIN/pat-from-image
PSNR=$BIN/examples/psnr

# Test images: name and ImageMagick source arguments (seeded where random).
images=(
    "rose|rose:"
    "wizard|wizard:"
    "logo|logo:"
    "granite|granite:"
    "netscape|netscape:"
    "plasma|-seed 7 -size 256x256 plasma:fractal"
    "plasma2|-seed 3 -size 256x256 plasma:green-yellow"
    "gradient|-size 256x256 gradient:navy-gold"
    "radial|-size 256x256 radial-gradient:white-darkred"
    "drawing|-size 256x256 gradient:skyblue-white -fill tomato -draw 'circle 90,90 90,30' -fill seagreen -draw 'rectangle 140,120 240,230' -stroke black -strokewidth 5 -draw 'line 10,240 240,10' -fill gold -stroke none -draw 'ellipse 70,190 50,30 0,360'"
)

for entry in "${images[@]}"; do
    name=${entry%%|*}
    src=${entry#*|}
    for n in 64 256; do
        # Centred square, resized, 8-bit RGB PNG.
        eval "$IM $src -resize ${n}x${n}^ -gravity center -extent ${n}x${n} -alpha off -depth 8 -define png:color-type=2 $OUT/$name-$n.png"
    done
done

now() { date +%s%N; }
# median_time CMD...: median wall time in ms over RUNS runs.
median_time() {
    local t=() s
    for _ in $(seq "$RUNS"); do
        s=$(now)
        "$@" >/dev/null 2>&1
        t+=($(( ($(now) - s) / 1000 )))
    done
    printf '%s\n' "${t[@]}" | sort -n | awk '{a[NR]=$1} END {printf "%.2f", a[int((NR+1)/2)]/1000}'
}

CSV=bench/out/pat_from_image.csv
echo "image,size,k,tool,psnr,linear_psnr,oklab_de,ms" > "$CSV"
for entry in "${images[@]}"; do
    name=${entry%%|*}
    for n in 64 256; do
        in=$OUT/$name-$n.png
        for k in 4 8 16 32; do
            base=$OUT/$name-$n-$k
            ours=(env "$OURS" --size "$n" --colors "$k" -o "$base-ours.pat" "$in")
            pq=(pngquant --nofs --force --output "$base-pngquant.png" "$k" "$in")
            im=("$IM" "$in" +dither -colors "$k" "$base-im.png")
            for tool in ours pngquant im; do
                case $tool in
                    ours) cmd=("${ours[@]}"); res=$base-ours.pat ;;
                    pngquant) cmd=("${pq[@]}"); res=$base-pngquant.png ;;
                    im) cmd=("${im[@]}"); res=$base-im.png ;;
                esac
                ms=$(median_time "${cmd[@]}")
                read -r p lp de < <("$PSNR" "$in" "$res")
                echo "$name,$n,$k,$tool,$p,$lp,$de,$ms" >> "$CSV"
            done
        done
    done
done

python3 - "$CSV" <<'PY'
import csv, sys, statistics as st
rows = list(csv.DictReader(open(sys.argv[1])))
cases = {}
for r in rows:
    cases.setdefault((int(r["size"]), int(r["k"]), r["image"]), {})[r["tool"]] = r
print("Mean over the 10 images. PSNR: 8-bit sRGB dB (higher is better); dE: mean OKLab x100 (lower is better);")
print("d = ours - peer in dB; wins = images where ours >= peer; time: median ms per run, ratio ours/peer.\n")
print("| size | K | ours PSNR | pngquant | IM | d pq | d IM | wins pq | wins IM | ours dE | pq dE | IM dE | ours ms | pq ms | IM ms | t ours/pq | t ours/IM |")
print("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|")
losses = []
for size in (64, 256):
    for k in (4, 8, 16, 32):
        cs = [v for (s, kk, _), v in cases.items() if s == size and kk == k]
        m = lambda t, f: st.mean(float(c[t][f]) for c in cs)
        wins = lambda t: sum(float(c["ours"]["psnr"]) >= float(c[t]["psnr"]) - 1e-9 for c in cs)
        for (s, kk, img), c in cases.items():
            if s == size and kk == k and float(c["ours"]["psnr"]) < float(c["pngquant"]["psnr"]):
                losses.append(f"{img} {s}x{s} K={k}: ours {c['ours']['psnr']} vs pngquant {c['pngquant']['psnr']}")
        print(f"| {size} | {k} | {m('ours','psnr'):.2f} | {m('pngquant','psnr'):.2f} | {m('im','psnr'):.2f} "
              f"| {m('ours','psnr')-m('pngquant','psnr'):+.2f} | {m('ours','psnr')-m('im','psnr'):+.2f} "
              f"| {wins('pngquant')}/{len(cs)} | {wins('im')}/{len(cs)} "
              f"| {m('ours','oklab_de'):.2f} | {m('pngquant','oklab_de'):.2f} | {m('im','oklab_de'):.2f} "
              f"| {m('ours','ms'):.1f} | {m('pngquant','ms'):.1f} | {m('im','ms'):.1f} "
              f"| {m('ours','ms')/m('pngquant','ms'):.2f} | {m('ours','ms')/m('im','ms'):.2f} |")
print()
print("Cases where ours has lower sRGB PSNR than pngquant:", len(losses))
for l in losses:
    print("  " + l)
PY
