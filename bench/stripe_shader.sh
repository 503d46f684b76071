#!/usr/bin/env bash
# The stripe shader alone (examples/stripe_shade.rs), until scene-render calls
# it per pixel: a receding ground plane and a wall facing the camera at
# 1024x768, with the nearest level, blended levels and the seed's rule
# (--cig-compat); time per frame (median of RUNS after a warm-up frame, the
# benchmarks' rule of bench/timing.py, one thread, linear-light colour
# before encoding) and RMSE/PSNR/share off by more than 4 against the exact
# box-filtered stripe reference, over the pixels wholly on one face.
# Writes bench/RESULTS-stripe-shader.md. Not run in CI.
# Usage: bench/stripe_shader.sh [RUNS]
set -euo pipefail
cd "$(dirname "$0")/.."
runs=${1:-9}
cargo build --release --quiet --example stripe_shade
target=${CARGO_TARGET_DIR:-target}
out=bench/RESULTS-stripe-shader.md
{
  echo "# Stripe shader: nearest level, blended levels, --cig-compat"
  echo
  echo "\`bench/stripe_shader.sh $runs\` at commit $(git rev-parse --short HEAD), $(date -u +%Y-%m-%d), $(nproc) cores, load average $(cut -d' ' -f1 /proc/loadavg) at the start."
  echo "Times are the median of $runs single-threaded frames after a warm-up frame (bench/timing.py's rule) and move with the machine's load; the RMSE does not."
  echo
  for map in runway furrow crops; do
    "$target/release/examples/stripe_shade" "fixtures/stripes/$map.map" "$runs"
    echo
  done
} >"$out.tmp"
mv "$out.tmp" "$out"
cat "$out"
