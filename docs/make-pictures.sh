#!/usr/bin/env bash
# Redraws the pictures the README shows. Needs ImageMagick (apt-get install
# imagemagick) only to set the tiles side by side.
set -euo pipefail
cd "$(dirname "$0")/.."
cargo build --release --quiet --bins
im=/usr/bin/convert-im6.q16
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
for p in brick wood weave mod bkgrnd pyr chex; do
  target/release/pat-tile --size 128x128 --scale 2 --background 255,255,255 \
    -o "$tmp/$p.png" "fixtures/patterns/$p.pat"
done
"$im" "$tmp"/{brick,wood,weave,mod,bkgrnd,pyr,chex}.png -bordercolor white -border 4 +append docs/patterns.png
