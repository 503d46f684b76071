#!/bin/sh
# How much of llvmpipe MSAA 4x's render time a triangle soup leaves for exact
# visibility once a plain f64 clipper (bench/clip_bound.rs, no project code)
# has cut its triangles into pixel fragments: the bound behind
# RESULTS-aa-scaling.md's reading of issue "Performance at scale", item 1.
# Not run in CI.
#
#   bench/clip_bound.sh [N ...] > bench/RESULTS-clip-bound.md
#
# Uses bench/aa_scaling.sh's scenes (generated into its work directory when
# missing) and its peer (bench/venv.sh).
set -eu
cd "$(dirname "$0")/.."
BENCH=aa-scaling
. bench/setup.sh
. bench/venv.sh
rustc --edition 2021 -C opt-level=3 -o "$WORK/clip_bound" bench/clip_bound.rs
echo "# The clipping bound of exact anti-aliasing"
echo
echo "Run $(date -u '+%Y-%m-%d %H:%M UTC') at commit $(git rev-parse --short HEAD) on $(uname -sm), $(nproc) cores,"
echo "load average $(cut -d' ' -f1-3 /proc/loadavg); $(rustc --version). Clipping: median of ${AA_RUNS:-3}"
echo "runs in one process (the file read once, not timed); llvmpipe: as bench/aa_scaling.sh."
echo
"$VENV/bin/python" bench/clip_bound.py "$WORK/clip_bound" "$WORK" "$@"
