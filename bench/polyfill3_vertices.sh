#!/bin/sh
# polyfill3 on polygons of many vertices: a sliver 100,000 rows tall (500 to
# 50,000 vertices a side) and a comb of 1,000 to 16,000 teeth in one row.
# Time against the vertex count, with the fitted exponent. Not run in CI.
#
#   bench/polyfill3_vertices.sh [--baseline BINDIR] > bench/RESULTS-polyfill3-vertices.md
#
# --baseline: another build's polyfill3 (its target/release) takes turns with
# this one, and the outputs are compared byte for byte. The driver is
# bench/polyfill3_vertices.py (Python standard library only).
set -eu
cd "$(dirname "$0")/.."
BENCH=polyfill3-vertices
. bench/setup.sh
echo "# polyfill3 on polygons of many vertices"
echo
echo "Run $(date -u '+%Y-%m-%d %H:%M UTC') at commit $(git rev-parse --short HEAD) on $(uname -sm), $(nproc) cores,"
echo "load average $(cut -d' ' -f1-3 /proc/loadavg): \`bench/polyfill3_vertices.sh${*:+ $*}\`."
echo "Whole process, median of ${RUNS:-3} after a warm-up (bench/timing.py)."
echo
exec python3 bench/polyfill3_vertices.py "$TARGET/release" "$WORK" "$@"
