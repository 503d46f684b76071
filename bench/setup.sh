# Sourced by the benchmark launchers, from the repository's root, with BENCH
# set to the benchmark's name: builds the tools (release) and sets TARGET
# (cargo's target directory) and WORK ($TARGET/bench-$BENCH, created).
TARGET=$(cargo metadata --format-version 1 --no-deps | python3 -c 'import json,sys; print(json.load(sys.stdin)["target_directory"])')
cargo build --release --bins >&2
WORK="$TARGET/bench-$BENCH"
mkdir -p "$WORK"
