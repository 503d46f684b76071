#!/usr/bin/env bash
# pat-from-image on large patterns against pngquant: 1024x1024, K = 256 (and 64).
# Not run in CI. Usage: bench/pat_from_image_large.sh [RUNS]   (default 5)
#
# The ten images of bench/pat_images.sh, each cut to its centred square and
# resized to 1024x1024 by ImageMagick (so all tools quantize the same pixels;
# the small ones are upscaled, which gives them 10^5-10^6 distinct colours).
# Time and peak memory: bench/timing.py (median of RUNS whole-process runs
# after one warm-up, ours and pngquant taking turns in each round; decode,
# quantize, write to a file). Ours writes a .pat,
# 84 MB of text at K = 256 (the thesis's format: one bit plane per colour),
# pngquant a PNG of about 1 MB. PSNR: examples/psnr.rs, 8-bit sRGB over RGB.
set -euo pipefail

RUNS=${1:-5}
cd "$(dirname "$0")/.."
OUT=bench/out/pat_from_image_large
mkdir -p "$OUT"
command -v pngquant >/dev/null && [ -x /usr/bin/convert ] || {
    apt-get update -qq
    DEBIAN_FRONTEND=noninteractive apt-get install -y -qq pngquant imagemagick
}
IM=/usr/bin/convert
cargo build --release --quiet --bin pat-from-image --example psnr
BIN=${CARGO_TARGET_DIR:-target}/release
N=1024

. bench/pat_images.sh
for entry in "${images[@]}"; do
    name=${entry%%|*}
    src=${entry#*|}
    [ -f "$OUT/$name.png" ] ||
        eval "$IM $src -resize ${N}x${N}^ -gravity center -extent ${N}x${N} -alpha off -depth 8 -define png:color-type=2 $OUT/$name.png"
done

echo "# pat-from-image at ${N}x${N} against pngquant"
echo
echo "Run $(date -u '+%Y-%m-%d %H:%M UTC') at commit $(git rev-parse --short HEAD) on $(nproc) cores,"
echo "load average $(cut -d' ' -f1-3 /proc/loadavg); $(pngquant --version | head -1 | sed 's/^/pngquant /')."
echo "Time: median of $RUNS whole-process runs after a warm-up, the three commands of a row taking turns (bench/timing.py); memory: peak RSS."
echo "PSNR: 8-bit sRGB over RGB against the ${N}x${N} input. d = ours - pngquant."
echo
echo "| image | K | colours in | ours PSNR | pngquant PSNR | d dB | ours s | ours s, no file | pngquant s | time ours/pq | no file ours/pq | ours MiB | pq MiB | memory ours/pq |"
echo "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"
for k in 256 64; do
    for entry in "${images[@]}"; do
        name=${entry%%|*}
        in=$OUT/$name.png
        # Ours, ours with the .pat going to /dev/null (timing.py discards
        # standard output: what the 84 MB file itself costs to write) and
        # pngquant, taking turns in each round, so that a slow spell of
        # this shared machine falls on all three.
        { read -r t_ours m_ours; read -r t_null _; read -r t_pq m_pq; } < <(
            python3 bench/timing.py --runs "$RUNS" \
                -- "$BIN/pat-from-image" --size $N --colors $k -o "$OUT/$name-$k.pat" "$in" \
                -- "$BIN/pat-from-image" --size $N --colors $k -o - "$in" \
                -- pngquant --nofs --force --output "$OUT/$name-$k-pq.png" $k "$in")
        read -r p_ours _ < <("$BIN/examples/psnr" "$in" "$OUT/$name-$k.pat")
        read -r p_pq _ < <("$BIN/examples/psnr" "$in" "$OUT/$name-$k-pq.png")
        colours=$($IM "$in" -format %k info:)
        python3 - "$name" "$k" "$colours" "$p_ours" "$p_pq" "$t_ours" "$t_null" "$t_pq" "$m_ours" "$m_pq" <<'PY'
import sys
name, k, colours, po, pp, to, tn, tp, mo, mp = sys.argv[1:]
po, pp, to, tn, tp, mo, mp = map(float, (po, pp, to, tn, tp, mo, mp))
print(f"| {name} | {k} | {colours} | {po:.3f} | {pp:.3f} | {po-pp:+.3f} | {to:.3f} | {tn:.3f} | {tp:.3f} | {to/tp:.2f} | {tn/tp:.2f} "
      f"| {mo/1024:.0f} | {mp/1024:.0f} | {mo/mp:.2f} |")
PY
    done
done

# Memory at the largest size: one 4096x4096 plasma, one run each.
big=$OUT/plasma-4096.png
[ -f "$big" ] || $IM -seed 7 -size 4096x4096 plasma:fractal -depth 8 -define png:color-type=2 "$big"
read -r t_ours m_ours < <(python3 bench/timing.py --runs 1 --warmup 0 -- \
    "$BIN/pat-from-image" --size 4096 --colors 256 -o - "$big")
read -r t_pq m_pq < <(python3 bench/timing.py --runs 1 --warmup 0 -- \
    pngquant --nofs --force --output "$OUT/plasma-4096-pq.png" 256 "$big")
echo
echo "4096x4096 plasma, K = 256, one run each (ours writing to /dev/null: the .pat is 1.3 GB):"
echo "ours $t_ours s, $((m_ours / 1024)) MiB; pngquant $t_pq s, $((m_pq / 1024)) MiB;" \
    "memory ours/pngquant $(python3 -c "print(f'{$m_ours / $m_pq:.2f}')")."
