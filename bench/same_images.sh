#!/bin/sh
# This build's images against a baseline build's, scene by scene (issue
# "Performance at scale": a change for speed must leave what is drawn as it
# was). Not run in CI.
#
#   bench/same_images.sh BASELINE_BINDIR > table
#
# BASELINE_BINDIR holds the baseline's scene-render (a release build of an
# earlier commit, e.g. from a git worktree). Needs the venv of bench/venv.sh
# for the texture benchmark's photograph (Pillow).
set -eu
cd "$(dirname "$0")/.."
BENCH=same-images
. bench/setup.sh
. bench/venv.sh
echo "Run $(date -u '+%Y-%m-%d %H:%M UTC') at commit $(git rev-parse --short HEAD) against $1."
echo
"$VENV/bin/python" bench/same_images.py "$TARGET/release" "$1" "$WORK"
