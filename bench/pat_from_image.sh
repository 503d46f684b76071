#!/usr/bin/env bash
# Benchmark of pat-from-image's quantizer against pngquant and ImageMagick.
# Not run in CI. Usage: bench/pat_from_image.sh [RUNS]   (RUNS: timing repeats, default 5)
#
# For 10 test images (ImageMagick's built-in photos, drawings and procedural
# images), each resized to 64x64 and 256x256, and K = 4, 8, 16, 32 colours, it
# runs ours (no dithering), `pngquant --nofs K` and `convert +dither -colors K`,
# measures sRGB PSNR, linear-light PSNR and mean OKLab error against the resized
# original (examples/psnr.rs), times each tool (bench/timing.py: median of RUNS
# whole-process runs after a warm-up: decode, quantize, write), and prints a
# table with ratios ours/peer. bench/pat_from_image_large.sh does 1024x1024.
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

. bench/pat_images.sh

for entry in "${images[@]}"; do
    name=${entry%%|*}
    src=${entry#*|}
    for n in 64 256; do
        # Centred square, resized, 8-bit RGB PNG.
        eval "$IM $src -resize ${n}x${n}^ -gravity center -extent ${n}x${n} -alpha off -depth 8 -define png:color-type=2 $OUT/$name-$n.png"
    done
done

# median_time CMD...: median wall time in ms over RUNS runs after a warm-up
# (bench/timing.py, the benchmarks' one timing rule).
median_time() {
    python3 bench/timing.py --runs "$RUNS" -- "$@" | awk '{printf "%.2f", $1 * 1000}'
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
