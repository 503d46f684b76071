#!/bin/sh
# What each of scene-render's work-saving skips saves (issue 7): per skip a
# scene where it matters, rendered with and without it (`--no-skip`), median
# of 5 render phases after a warm-up with one thread (bench/timing.py), ratio, and a byte-identical output check;
# then a stream referencing 1 of 200 pattern files against one referencing
# all 200. The driver is bench/skips.py (Python standard library only).
#
#   bench/skips.sh > bench/RESULTS-skips.md
set -eu
cd "$(dirname "$0")/.."
BENCH=skips
. bench/setup.sh
python3 bench/skips.py "$TARGET/release" "$WORK"
