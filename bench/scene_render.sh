#!/bin/sh
# scene-render against its own reference and against Mesa's llvmpipe.
#
#   bench/scene_render.sh > bench/RESULTS-scene-render.md
#
# Installs its peers itself: a Python venv with moderngl and numpy (pip), and
# Mesa's EGL/llvmpipe (apt-get, when root and missing). Prints one Markdown
# document: machine, table, notes. Not run in CI: times depend on the machine.
set -eu
cd "$(dirname "$0")/.."
ROOT=$(pwd)
BENCH=scene-render
. bench/setup.sh
SR="$TARGET/release/scene-render"

. bench/venv.sh

# Demo 2 (App. C, examples/scenes/demo2.json): through polyfill3 when it is built
# (it is, once polyfill3 is on the branch), else through the
# stand-in partitioner bench/demo2_scene.py (same docs/stream-format.md object-mode rule).
for incr in 2 1; do
    scene="$WORK/demo2-incr$incr.ndjson"
    if [ -x "$TARGET/release/polyfill3" ]; then
        # The pyramid's texel side (incr 2 in the thesis) set to $incr.
        sed "s/\"incr\": 2,/\"incr\": $incr,/" examples/scenes/demo2.json > examples/scenes/.bench-demo2.json
        "$TARGET/release/polyfill3" examples/scenes/.bench-demo2.json > "$scene"
        rm -f examples/scenes/.bench-demo2.json
    else
        python3 bench/demo2_scene.py fixtures/patterns "$incr" > "$scene"
    fi
done
tris="$WORK/triangles-1M.ndjson"
[ -f "$tris" ] || "$VENV/bin/python" bench/scene_render_bench.py --random-triangles 1000000 "$tris"

echo "# scene-render benchmark"
echo
echo "Run $(date -u '+%Y-%m-%d %H:%M UTC') on $(uname -sm), $(nproc) cores"
echo "($(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //')), load average $(cut -d' ' -f1-3 /proc/loadavg)."
echo "Commit $(git rev-parse --short HEAD). Images $(echo 1024x768), median of 5 runs of the whole pipeline after a warm-up"
echo "(scene-render: read the stream, render, write the PNG; llvmpipe: upload, draw, resolve,"
echo "read back, encode, write the PNG; the stream's parsing in Python is left out of llvmpipe's time)."
echo "'Render only' is scene-render's projection-to-pixels time (--timings: without reading the JSON"
echo "and writing the PNG) and llvmpipe's upload, draw, MSAA resolve and read back: the comparable pair."
echo "Errors are against \`scene-render --reference\`, in 8-bit sRGB units over RGB."
echo "The '-cull' scenes drop back faces in both renderers (--cull back; GL_CULL_FACE), as demo 2's"
echo "Makefile does; the others draw every face and let the depth test hide the back ones."
echo
"$VENV/bin/python" bench/scene_render_bench.py "$SR" "$WORK" \
    "demo2-incr2=$WORK/demo2-incr2.ndjson:demo2" \
    "demo2-incr1=$WORK/demo2-incr1.ndjson:demo2" \
    "demo2-incr2-cull=$WORK/demo2-incr2.ndjson:demo2cull" \
    "demo2-incr1-cull=$WORK/demo2-incr1.ndjson:demo2cull" \
    "triangles-1M=$tris:tris"
