#!/bin/sh
# Crowded pixels under --aa exact (a fan of N triangles round one vertex, a
# strip of N thin triangles), time against N (bench/crowded_pixels.py), this
# build against a baseline build in one run.
#
#   bench/crowded_pixels.sh [BASELINE_BINDIR] > bench/RESULTS-crowded-pixels.md
#
# Not run in CI. CARGO_TARGET_DIR is honoured.
set -eu
cd "$(dirname "$0")/.."
target=${CARGO_TARGET_DIR:-target}
cargo build --release --quiet --bin scene-render
echo "# Crowded pixels"
echo
echo "Run $(date -u '+%Y-%m-%d %H:%M UTC') at commit $(git rev-parse --short HEAD) on $(nproc) cores, load average $(cut -d' ' -f1-3 /proc/loadavg)${1:+; baseline: $1}."
echo
python3 bench/crowded_pixels.py "$target/release" "$@"
