#!/bin/sh
# Direct texturing in scene-render: time and error against --reference, per
# anti-aliasing mode, and the polyfill3 | scene-render path beside it.
#
#   bench/texture.sh > bench/RESULTS-texture.md
#
# Three scenes: a checkered plane receding to the horizon (heavy
# minification), a close-up wall (magnification, crisp texel edges), and the
# thesis's demo 2 (App. C) drawn directly; each texture filter (--filter)
# beside the default exact box filter. Prints one Markdown document.
# llvmpipe is not run here (see the notes it prints).
set -eu
cd "$(dirname "$0")/.."
rm -f "${CARGO_TARGET_DIR:-target}/bench-texture/ref-notes"
TARGET=$(cargo metadata --format-version 1 --no-deps | python3 -c 'import json,sys; print(json.load(sys.stdin)["target_directory"])')
cargo build --release --bins >&2
SR="$TARGET/release/scene-render"
P3="$TARGET/release/polyfill3"
WORK="$TARGET/bench-texture"
mkdir -p "$WORK"
ROOT=$(pwd)

# A 16x16 two-colour checker of single texels.
python3 - "$WORK" <<'PY'
import json, sys
w = sys.argv[1]
s = "16 2\n230 230 230\n"
even = "".join("%04x\n" % (0xAAAA if r % 2 == 0 else 0x5555) for r in range(16))
odd = "".join("%04x\n" % (0x5555 if r % 2 == 0 else 0xAAAA) for r in range(16))
s += even + "20 20 120\n" + odd
open(w + "/checker.pat", "w").write(s)
# The plane: 400 x 400 units of 1-unit texels, from z = -1 to -401.
plane = {"vertices": [[-200, 0, -1], [200, 0, -1], [200, 0, -401], [-200, 0, -401]],
         "color": [128, 128, 128], "pattern": {"file": "checker.pat", "incr": 1}}
open(w + "/plane.json", "w").write(json.dumps(plane) + "\n")
# The wall: 16 x 12 texels of 1 unit, seen from 8 units, slightly turned.
wall = {"vertices": [[-8, -6, -10], [8, -6, -7], [8, 6, -7], [-8, 6, -10]],
        "color": [128, 128, 128], "pattern": {"file": "checker.pat", "incr": 1, "rotate": 7}}
open(w + "/wall.json", "w").write(json.dumps(wall) + "\n")
PY
sed 's#"\.\./\.\./fixtures/#"'"$ROOT"'/fixtures/#g' examples/scenes/demo2.json > "$WORK/demo2.json"

# name | scene | size | camera flags
scenes="plane|plane.json|320x240|--perspective 60,1.333,0.5,1000 --lookat 0,2,0,0,1.2,-20
wall|wall.json|640x480|--perspective 60,1.333,0.5,100 --lookat 0,0,0,0,0,-10
demo2|demo2.json|1024x768|--perspective 55,1,0,1000 --lookat 0,100,-5,0,0,-900 --cull back"

# Best of 3 wall-clock seconds of a shell command.
best3() {
    b=
    for _ in 1 2 3; do
        t0=$(date +%s.%N); sh -c "$1" >/dev/null 2>"$WORK/err"; t1=$(date +%s.%N)
        t=$(echo "$t1 - $t0" | bc)
        if [ -z "$b" ] || [ "$(echo "$t < $b" | bc)" = 1 ]; then b=$t; fi
    done
    printf '%.3f' "$b"
}
render_time() { sed -n 's/.*render \([0-9.]*\) s.*/\1/p' "$WORK/err"; }
rmse() { "$SR" --image "$1" --compare "$2" --json | python3 -c 'import json,sys; c=json.load(sys.stdin)["compare"]; print("%.4f | %d" % (c["rmse"], c["max_error"]))'; }

echo "# Direct texturing benchmark"
echo
echo "Run $(date -u '+%Y-%m-%d %H:%M UTC') on $(uname -sm), $(nproc) cores"
echo "($(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //')), load average $(cut -d' ' -f1-3 /proc/loadavg)."
echo "Commit $(git rev-parse --short HEAD). Whole process: best of 3 wall-clock runs (read, render,"
echo "write the PNG). Render: scene-render's --timings render phase of the last run. Errors against"
echo "\`scene-render --reference\` of the same textured scene, 8-bit sRGB over RGB (RMSE, largest error)."
echo
echo "| scene | path | render s | whole s | RMSE | max |"
echo "|---|---|---:|---:|---:|---:|"
echo "$scenes" | while IFS='|' read -r name scene size cam; do
    cd "$WORK"
    t0=$(date +%s.%N)
    "$SR" --size "$size" $cam --reference "$scene" -o "$name-ref.png" 2>"$WORK/ref-err"
    t1=$(date +%s.%N)
    echo "| $name | reference | | $(printf '%.3f' "$(echo "$t1 - $t0" | bc)") | 0 | 0 |"
    for aa in exact ss16 none; do
        whole=$(best3 "'$SR' --size $size $cam --aa $aa --timings $scene -o $name-$aa.png")
        echo "| $name | direct --aa $aa | $(render_time) | $whole | $(rmse "$name-$aa.png" "$name-ref.png") |"
    done
    for f in point bilinear mip-point mip-bilinear mip-point-linear trilinear ewa; do
        whole=$(best3 "'$SR' --size $size $cam --filter $f --timings $scene -o $name-$f.png")
        echo "| $name | direct --filter $f | $(render_time) | $whole | $(rmse "$name-$f.png" "$name-ref.png") |"
    done
    whole=$(best3 "'$P3' $scene | '$SR' --size $size $cam --timings -o $name-p3.png")
    echo "| $name | polyfill3 \\| --aa exact | $(render_time) | $whole | $(rmse "$name-p3.png" "$name-ref.png") |"
    printf '    %s: %s\n' "$name" "$(cat "$WORK/ref-err")" >> "$WORK/ref-notes"
    cd "$ROOT"
done
echo
echo "Reference error estimates (their own, per scene in order):"
echo
cat "$WORK/ref-notes"
rm -f "$WORK/ref-notes"
echo
echo "The machine is shared (see the load average): times vary by up to 2x between runs."
echo
echo "The --filter rows use --aa exact (exact coverage, each fragment flat-coloured by the filter"
echo "at the pixel centre; mag filter: point for the point-sampled filters, bilinear for the others)."
echo "Their error against the box-filtered reference is the filter's own blur or aliasing, not a"
echo "defect: the reference integrates the box filter."
echo
echo "Not measured here: llvmpipe (moderngl) with textures."
