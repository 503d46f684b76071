#!/bin/sh
# scene-render's peak memory per polygon and per pixel (issue "Performance at
# scale", item 3). Not run in CI.
#
#   bench/memory.sh > bench/RESULTS-memory.md
#
# Peak RSS (bench/timing.py: one run each, through GNU time, so the
# process's own) of: an empty stream (the baseline),
# the seeded random triangles of bench/random_triangles.py (200,000 and
# 1,000,000, about four layers a pixel) at 1024x768, and one triangle at
# 1024x1024, 4096x4096 and 16384x16384, and with --background none, with
# --depth 16 and with both at the first two; bytes per triangle above the
# baseline, and bytes per pixel between 1024x1024 and 4096x4096. And
# pat-tile's peak filling 1024x1024 and 16384x16384 with a pattern that has
# transparent texels (RGBA out), written a row at a time.
set -eu
cd "$(dirname "$0")/.."
BENCH=memory
. bench/setup.sh
SR="$TARGET/release/scene-render"
: > "$WORK/empty.ndjson"
echo '{"vertices":[[0,0],[1000,0],[0,1000]],"color":[200,100,50]}' > "$WORK/one.ndjson"
for n in 200000 1000000; do
    [ -f "$WORK/tri-$n.ndjson" ] || python3 bench/random_triangles.py $n auto > "$WORK/tri-$n.ndjson"
done
peak() { python3 bench/timing.py --runs 1 --warmup 0 -- "$SR" "$@" -o "$WORK/out.png" | cut -d' ' -f2; }
base=$(peak --size 1024x768 "$WORK/empty.ndjson")
echo "# scene-render memory"
echo
echo "Run $(date -u '+%Y-%m-%d %H:%M UTC') at commit $(git rev-parse --short HEAD); peak RSS of one run each (bench/timing.py, through GNU time)."
echo
echo "| input | --aa | peak MiB | bytes per triangle above the empty stream |"
echo "|---|---|---:|---:|"
echo "| empty stream, 1024x768 | exact | $((base / 1024)) | |"
for run in "200000 exact" "1000000 exact" "1000000 none"; do
    set -- $run
    kb=$(peak --size 1024x768 --aa "$2" "$WORK/tri-$1.ndjson")
    echo "| $1 random triangles, 1024x768 | $2 | $((kb / 1024)) | $(( (kb - base) * 1024 / $1 )) |"
done
small=$(peak --size 1024x1024 "$WORK/one.ndjson")
large=$(peak --size 4096x4096 "$WORK/one.ndjson")
huge=$(peak --size 16384x16384 "$WORK/one.ndjson")
echo
echo "One triangle: 1024x1024 $((small / 1024)) MiB, 4096x4096 $((large / 1024)) MiB:" \
    "$(awk "BEGIN { printf \"%.1f\", ($large - $small) * 1024 / (4096 * 4096 - 1024 * 1024) }")" \
    "bytes per pixel; 16384x16384 $((huge / 1024)) MiB."
small=$(peak --size 1024x1024 --background none "$WORK/one.ndjson")
large=$(peak --size 4096x4096 --background none "$WORK/one.ndjson")
echo
echo "One triangle, --background none (RGBA, drawn over black and over white):" \
    "1024x1024 $((small / 1024)) MiB, 4096x4096 $((large / 1024)) MiB:" \
    "$(awk "BEGIN { printf \"%.1f\", ($large - $small) * 1024 / (4096 * 4096 - 1024 * 1024) }")" \
    "bytes per pixel."
for bg in "" "--background none"; do  # $bg unquoted: empty, or two words
    small=$(peak --size 1024x1024 --depth 16 $bg "$WORK/one.ndjson")
    large=$(peak --size 4096x4096 --depth 16 $bg "$WORK/one.ndjson")
    echo
    echo "One triangle, --depth 16${bg:+ $bg}: 1024x1024 $((small / 1024)) MiB, 4096x4096 $((large / 1024)) MiB:" \
        "$(awk "BEGIN { printf \"%.1f\", ($large - $small) * 1024 / (4096 * 4096 - 1024 * 1024) }")" \
        "bytes per pixel."
done
PT="$TARGET/release/pat-tile"
tile_peak() { python3 bench/timing.py --runs 1 --warmup 0 -- "$PT" --size "$1" fixtures/patterns/bkgrnd.pat -o "$WORK/tiled.png" | cut -d' ' -f2; }
echo
echo "pat-tile, fixtures/patterns/bkgrnd.pat (RGBA): 1024x1024 $(( $(tile_peak 1024x1024) / 1024 )) MiB," \
    "16384x16384 $(( $(tile_peak 16384x16384) / 1024 )) MiB."
