#!/usr/bin/env bash
# Memory of a 4096x4096 image texture (issue 19, item 1): renders a plane
# receding over it at 640x480 under an address-space limit (ulimit -v) per
# resolver/filter, and prints each run's peak resident memory
# (/usr/bin/time -v). Fails if any run exceeds its limit.
#
#   bash bench/image_texture_memory.sh [BINDIR]    (default target/release)
#
# Limits (virtual memory, MiB): --aa none 400, --filter trilinear (its MIP
# pyramid built) 600, the exact default 400 (its cells are summed as they
# are cut). The texels cost 64 MB (sRGB codes); figures are in
# docs/rendering.md, "Image textures".
set -euo pipefail
cd "$(dirname "$0")/.."
BIN=${1:-target/release}
T=$(mktemp -d)
trap 'rm -rf "$T"' EXIT
"$BIN/pat-tile" fixtures/patterns/earth.pat --size 4096x4096 -o "$T/big.png"
cat > "$T/plane.json" <<'JSON'
{"vertices":[[-4,-1,-1.5],[4,-1,-1.5],[4,-1,-40],[-4,-1,-40]],"uv":[[0,0],[4096,0],[4096,4096],[0,4096]],"color":[90,90,90],"pattern":{"file":"big.png"}}
JSON
status=0
for run in "none:409600:--aa none" "trilinear:614400:--filter trilinear" "exact:409600:--aa exact"; do
    IFS=: read -r name limit flags <<<"$run"
    # shellcheck disable=SC2086
    if (ulimit -v "$limit"; /usr/bin/time -v "$BIN/scene-render" --size 640x480 \
            --perspective 60,1.333,0.1,100 --lookat 0,0.5,1,0,-0.5,-5 $flags \
            "$T/plane.json" -o "$T/$name.png" 2> "$T/$name.time"); then
        rss=$(awk '/Maximum resident/ {print $NF}' "$T/$name.time")
        echo "$name: peak RSS $((rss / 1024)) MB (limit $((limit / 1024)) MB virtual)"
    else
        echo "$name: FAILED under $((limit / 1024)) MB" >&2
        status=1
    fi
done
exit $status
