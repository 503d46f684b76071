#!/bin/sh
# Fuzzes polyfill3 with inputs off their plane within --planarity-tol (the two
# review fuzzers docs/polyfill3.md quotes): every stream it writes for an
# input scene-render takes, cut plain, with --merge and with --merge=blocks,
# must be taken by scene-render. Prints a Markdown table of the counts; exits
# 1 if scene-render refused a stream of this build (the inputs are left in
# WORK/fails/). Not run in CI. The driver is bench/polyfill3_fuzz.py (Python
# standard library only; its docstring says what is drawn and counted).
#
#   bench/polyfill3_fuzz.sh [--baseline BINDIR] [--bin BINDIR] [--jobs J] [GENERATOR:SEED:N[:TOL] ...]
#
# Default: this checkout's release build, the six runs of the docs' figures
# (4,600 inputs). --baseline: another build's polyfill3 and scene-render
# run beside it, and the streams compared byte for byte.
set -eu
cd "$(dirname "$0")/.."
BENCH=polyfill3-fuzz
. bench/setup.sh
rm -rf "$WORK/fails" "$WORK/scratch"
echo "Run $(date -u '+%Y-%m-%d %H:%M UTC') at commit $(git rev-parse --short HEAD) on $(nproc) cores,"
echo "load average $(cut -d' ' -f1-3 /proc/loadavg): \`bench/polyfill3_fuzz.sh${*:+ $*}\`"
echo
exec python3 bench/polyfill3_fuzz.py --bin "$TARGET/release" --work "$WORK" "$@"
