#!/bin/sh
# A fan of N triangles round one vertex under --aa exact, time against N
# (bench/fan.py), this build against a baseline build in one run.
#
#   bench/fan.sh [BASELINE_BINDIR] > bench/RESULTS-fan.md
#
# Not run in CI. CARGO_TARGET_DIR is honoured.
set -eu
cd "$(dirname "$0")/.."
target=${CARGO_TARGET_DIR:-target}
cargo build --release --quiet --bin scene-render
echo "# Fans of triangles round one vertex"
echo
echo "Run $(date -u '+%Y-%m-%d %H:%M UTC') at commit $(git rev-parse --short HEAD) on $(nproc) cores, load average $(cut -d' ' -f1-3 /proc/loadavg)${1:+; baseline: $1}."
echo
python3 bench/fan.py "$target/release" "$@"
