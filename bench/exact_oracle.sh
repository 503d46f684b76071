#!/bin/sh
# An independent exact check of scene-render --aa exact: seeded scenes of 19
# kinds (bench/exact_oracle/gen.py) rendered to PNG and PFM and compared, every
# channel of every pixel, with an exact rational integration
# (bench/exact_oracle/oracle.py, written from the docs, not from the Rust code).
# Not run in CI.
#
#   bench/exact_oracle.sh > bench/RESULTS-exact-oracle.md
#   bench/exact_oracle.sh --kinds tilted,slivers --seeds 1-10 > /tmp/oracle.md
#
# Arguments go to bench/exact_oracle/run.py (--kinds, --seeds, --jobs, --threads);
# the default, every kind at seeds 4-8 on as many jobs as cores, takes four to six
# minutes on two cores. Python's gmpy2 and mpmath (pip from PyPI) go into a venv
# under the target dir; the scenes, images and results.ndjson into
# $WORK/exact-oracle-run.
set -eu
cd "$(dirname "$0")/.."
BENCH=exact-oracle
. bench/setup.sh
VENV="$TARGET/bench-exact-oracle/venv"
if ! "$VENV/bin/python" -c 'import gmpy2, mpmath' 2>/dev/null; then
    python3 -m venv "$VENV" >&2
    "$VENV/bin/pip" install -q gmpy2 mpmath >&2
fi
echo "# Exact oracle: --aa exact against exact rational integration"
echo
echo "Run $(date -u '+%Y-%m-%d %H:%M UTC') at commit $(git rev-parse --short HEAD) on $(uname -sm), $(nproc) cores,"
echo "load average $(cut -d' ' -f1-3 /proc/loadavg). scene-render --aa exact --threads 1, 8-bit PNG"
echo "and PFM, against bench/exact_oracle/oracle.py (exact rationals, colours to 60 digits)."
echo "'Closest margin' is how near an exact value came to a rounding boundary of the 8-bit"
echo "codes (in codes); 'tie-aware' takes near-coplanar polygons as tied within 1e-9 (1 + |z|)"
echo "(docs/rendering.md, *Visibility and ties*); 'rejected' scenes are inputs scene-render refused."
echo
"$VENV/bin/python" bench/exact_oracle/run.py "$TARGET/release/scene-render" "$WORK" --jobs "$(nproc)" "$@"
