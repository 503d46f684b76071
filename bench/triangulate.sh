#!/usr/bin/env bash
# Triangulation and simplicity test (issue 16): prints bench/RESULTS-triangulate.md.
#
#   bash bench/triangulate.sh [OLD_BINDIR] > bench/RESULTS-triangulate.md
#
# 1. `cargo bench --bench triangulate`: ear clipping (as raster::project did it
#    before) against geom::triangulate on concave stars and notched circles of
#    1,000 to 1,000,000 vertices, and the simplicity test every record passes.
# 2. The tools end to end on a concave star of 1,000,000 vertices (radii 7 and
#    5 around (8, 8)): scene-render in each --aa mode at 16x16 and 1024x768, and
#    polyfill3 with a pattern; /usr/bin/time's wall and CPU seconds and peak
#    memory. With OLD_BINDIR (binaries built before this change) the same
#    commands run with those too, at 10,000 vertices as well (the most the
#    old scene-render drew; past that it refused the star).
# Not run in CI. CARGO_TARGET_DIR is honoured; TIMEOUT (seconds, default 300)
# bounds each command.
set -euo pipefail
cd "$(dirname "$0")/.."
old=${1:-}
target=${CARGO_TARGET_DIR:-target}
cargo build --release --quiet --bins
bin=$target/release

echo "# Triangulation and simplicity test: benchmark results"
echo
echo "Run: \`bash bench/triangulate.sh${old:+ OLD_BINDIR}\` (benches/triangulate.rs and the tools end to end),"
echo "$(date -u '+%Y-%m-%d %H:%M UTC'), commit $(git rev-parse --short HEAD)$(git diff --quiet HEAD -- src benches || echo ' (with uncommitted changes)'),"
echo "$(rustc --version), release profile, one thread, on 2 cores shared with other builds:"
echo "load average at the start: $(uptime | sed 's/.*load average: //')."
echo
cargo bench --quiet --bench triangulate 2>/dev/null

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cp fixtures/patterns/brick.pat "$work/"
python3 - "$work" <<'PY'
import math, sys
for n in (10_000, 1_000_000):
    pts = ",".join(
        "[%r,%r]" % (8 + r * math.cos(a), 8 + r * math.sin(a))
        for i in range(n)
        for a, r in [(2 * math.pi * i / n, 7.0 if i % 2 == 0 else 5.0)]
    )
    with open(f"{sys.argv[1]}/star{n}.json", "w") as f:
        f.write('{"vertices":[%s],"color":[255,255,255]}\n' % pts)
    with open(f"{sys.argv[1]}/star{n}-pat.json", "w") as f:
        f.write('{"vertices":[%s],"color":[255,255,255],"pattern":{"file":"brick.pat"}}\n' % pts)
PY

echo
echo "## The tools end to end on a concave star"
echo
echo "Load average now: $(uptime | sed 's/.*load average: //'). CPU = user + system seconds."
echo
echo "| binaries | command | vertices | wall | CPU | peak memory | result |"
echo "|---|---|---:|---:|---:|---:|---|"
run() { # LABEL BINDIR N TOOL ARGS...
    local label=$1 dir=$2 n=$3 tool=$4
    shift 4
    local t rc=0 wall user sys mem
    /usr/bin/time -o "$work/time" -f '%e %U %S %M' \
        timeout "${TIMEOUT:-300}" "$dir/$tool" "$@" >/dev/null 2>"$work/err" || rc=$?
    t=$(tail -1 "$work/time")
    local res="ok"
    if [ "$rc" -eq 124 ]; then res="timed out after ${TIMEOUT:-300} s"
    elif [ "$rc" -ne 0 ]; then res="exit $rc: $(sed 's/.*record 0: //' "$work/err" | head -c 90)..."; fi
    read -r wall user sys mem <<<"$t"
    printf '| %s | `%s %s` | %s | %s s | %.2f s | %d MB | %s |\n' \
        "$label" "$tool" "$*" "$n" "$wall" "$(awk -v u="$user" -v s="$sys" 'BEGIN { print u + s }')" "$((mem / 1024))" "$res"
}
sets=("new:$bin")
[ -n "$old" ] && sets+=("old:$old")
for s in "${sets[@]}"; do
    label=${s%%:*}; dir=${s#*:}
    sizes=(1000000)
    [ -n "$old" ] && sizes=(10000 1000000)
    for n in "${sizes[@]}"; do
        (
            cd "$work"
            for aa in exact none ss16; do
                run "$label" "$dir" "$n" scene-render --size 16x16 --aa "$aa" -o out.png "star$n.json"
            done
            run "$label" "$dir" "$n" scene-render --size 1024x768 --ortho2 0,16,0,12 --aa exact -o out.png "star$n.json"
            run "$label" "$dir" "$n" polyfill3 -o out.ndjson "star$n-pat.json"
        )
    done
done
