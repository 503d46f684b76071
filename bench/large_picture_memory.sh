#!/usr/bin/env bash
# Peak memory of pat-from-image on large pictures (issue 17, item 12): valid
# RGB PNGs of 8000^2, 12000^2 and 14000^2 pixels (written here with Python's
# zlib), each turned into the default 64x64 pattern; prints the whole
# process's peak resident memory (/usr/bin/time -v) and bytes per picture
# pixel. A load case, not a test: it takes about a minute. Then the palette
# search's worst case: a 4096x4096 picture whose 16.7 million pixels all
# differ, to a 4096x4096 pattern of 256 colours (written to /dev/null), and
# bytes per pattern texel.
#
#   bash bench/large_picture_memory.sh [BINDIR]    (default target/release)
set -euo pipefail
cd "$(dirname "$0")/.."
BIN=${1:-target/release}
T=$(mktemp -d)
trap 'rm -rf "$T"' EXIT
echo "| picture | file MB | time s | peak RSS MB | bytes per pixel |"
echo "|---|---:|---:|---:|---:|"
for side in 8000 12000 14000; do
    python3 - "$side" "$T/p.png" <<'PY'
import struct, sys, zlib
w = h = int(sys.argv[1])
def chunk(t, d):
    return struct.pack(">I", len(d)) + t + d + struct.pack(">I", zlib.crc32(t + d) & 0xffffffff)
c = zlib.compressobj(1)
# A horizontal ramp, so the picture is not one colour.
row = b"\0" + bytes((x * 255 // w) for x in range(w) for _ in range(3))
data = b"".join(c.compress(row) for _ in range(h)) + c.flush()
with open(sys.argv[2], "wb") as f:
    f.write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0))
            + chunk(b"IDAT", data) + chunk(b"IEND", b""))
PY
    /usr/bin/time -v "$BIN/pat-from-image" "$T/p.png" -o "$T/p.pat" 2> "$T/time"
    rss=$(awk '/Maximum resident/ {print $NF}' "$T/time")
    secs=$(awk -F': ' '/Elapsed/ {print $2}' "$T/time")
    mb=$(du -m "$T/p.png" | cut -f1)
    echo "| ${side}x${side} | $mb | $secs | $((rss / 1024)) | $(python3 -c "print(f'{$rss * 1024 / ($side * $side):.1f}')") |"
done
python3 - "$T/d.png" <<'PY'
import struct, sys, zlib
w = h = 4096
def chunk(t, d):
    return struct.pack(">I", len(d)) + t + d + struct.pack(">I", zlib.crc32(t + d) & 0xffffffff)
c = zlib.compressobj(1)
# Every pixel its own colour: red and green the position in a 256x256 block,
# blue the block.
data = b"".join(c.compress(b"\0" + bytes(v for x in range(w) for v in (x & 255, y & 255, (y >> 8) * 16 + (x >> 8))))
                for y in range(h)) + c.flush()
with open(sys.argv[1], "wb") as f:
    f.write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0))
            + chunk(b"IDAT", data) + chunk(b"IEND", b""))
PY
/usr/bin/time -v "$BIN/pat-from-image" --size 4096 --colors 256 "$T/d.png" -o - > /dev/null 2> "$T/time"
rss=$(awk '/Maximum resident/ {print $NF}' "$T/time")
secs=$(awk -F': ' '/Elapsed/ {print $2}' "$T/time")
echo
echo "4096x4096, every pixel its own colour, to a 4096x4096 pattern of 256 colours: $secs," \
    "peak $((rss / 1024)) MB, $(python3 -c "print(f'{$rss * 1024 / (4096 * 4096):.1f}')") bytes a texel."
