#!/bin/sh
# Reading and writing the stream, and the polyfill3 | scene-render pipeline
# against scene-render texturing directly (issue "Performance at scale",
# item 2). Not run in CI.
#
#   bench/stream_speed.sh [BASELINE_BINDIR] > bench/RESULTS-stream.md
#
# BASELINE_BINDIR: a directory with another build's scene-render and
# polyfill3, measured in the same run, side by side.
set -eu
cd "$(dirname "$0")/.."
BENCH=stream
. bench/setup.sh
echo "# Reading and writing the stream"
echo
echo "Run $(date -u '+%Y-%m-%d %H:%M UTC') at commit $(git rev-parse --short HEAD) on $(nproc) cores,"
echo "load average $(cut -d' ' -f1-3 /proc/loadavg)${1:+; baseline: $1}."
echo
python3 bench/stream_speed.py "$TARGET/release" "$WORK" "$@"
