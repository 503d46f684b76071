#!/bin/sh
# A large frame with little drawn in it: the time and memory of
# scene-render --aa exact as the frame grows around the same 10,000
# triangles (1024x1024 to 16384x16384), against a baseline build if given
# and llvmpipe MSAA 4x up to 4096x4096. Not run in CI.
#
#   bench/large_frame.sh [BASELINE_RELEASE_DIR] > bench/RESULTS-large-frame.md
#
# Installs its peer as bench/scene_render.sh does (bench/venv.sh).
set -eu
cd "$(dirname "$0")/.."
BENCH=large-frame
. bench/setup.sh
. bench/venv.sh
echo "# A large frame with little drawn"
echo
echo "Run $(date -u '+%Y-%m-%d %H:%M UTC') at commit $(git rev-parse --short HEAD) on $(uname -sm), $(nproc) cores,"
echo "load average $(cut -d' ' -f1-3 /proc/loadavg)${1:+; baseline: $1}. Times: median of ${FRAME_RUNS:-3} after a warm-up,"
echo "the builds taking turns (bench/timing.py); 'render' is scene-render's render phase (--timings)"
echo "and llvmpipe's upload, draw, MSAA resolve and read back; peak: this build, one run."
echo
"$VENV/bin/python" bench/large_frame.py "$TARGET/release/scene-render" "$WORK" ${1:+"$1/scene-render"}
