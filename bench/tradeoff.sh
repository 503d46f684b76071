#!/bin/sh
# The run-time-against-error trade-off study (issue 5), one command:
#
#   bench/tradeoff.sh > bench/RESULTS-tradeoff.md     # also draws docs/tradeoff.png
#
# On the texturing benchmark's three scenes (plane, wall, demo 2), demo 1 and
# our own "tiles" (384 small tilted checker tiles at grazing angles), every
# method: scene-render direct at --aa none/ss4/ss16/exact (and each --filter
# when the binary has it), polyfill3 at incr x4, x2, x1, x0.5 then
# scene-render --aa exact, and llvmpipe at nearest/trilinear/aniso16 with and
# without MSAA 4x; each the median of 5 runs, measured against
# scene-render --reference. Methods are the METHODS list at the top of
# bench/texbench.py (add one there). Takes a few minutes.
set -eu
cd "$(dirname "$0")/.."
BENCH=tradeoff
. bench/setup.sh
mkdir -p docs
. bench/venv.sh
"$VENV/bin/python" bench/texbench.py tradeoff "$TARGET/release" "$WORK" docs/tradeoff.png
