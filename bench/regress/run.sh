#!/usr/bin/env bash
# Regression corpus of the five patkit tools.
#
#   bash bench/regress/run.sh BINDIR OUTDIR
#
# Runs every tool invocation below with the binaries in BINDIR, working from
# the repository (read only) or from generated-input directories inside OUTDIR,
# and writes into OUTDIR only:
#   log/NAME.out  log/NAME.err  log/NAME.rc   stdout, stderr, exit status of each command
#   o/...                                     every output file (-o), named after the command
#   scenes/...                                generated inputs (gen.py: tests', bench's, docs' scenes)
#   commands.tsv                              NAME, working directory, command (BINDIR/OUTDIR masked)
# Files named *.nocmp hold timing figures and are not compared; each has a
# comparable twin with the figures masked (log/NAME.err). The absolute
# OUTDIR and BINDIR are replaced by @OUT@ and @BIN@ in every text file at the end.
# Compare two corpora with bench/regress/compare.sh DIR_A DIR_B.
set -u
if [ $# -ne 2 ]; then echo "usage: bash $0 BINDIR OUTDIR" >&2; exit 2; fi
ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
HERE=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
BIN=$(cd "$1" && pwd) || exit 2
for t in pat-from-image pat-info pat-tile polyfill3 scene-render; do
    [ -x "$BIN/$t" ] || { echo "run.sh: $BIN/$t is missing" >&2; exit 2; }
done
mkdir -p "$2" || exit 2
OUT=$(cd "$2" && pwd) || exit 2
case "$OUT" in /|"$ROOT"|"$ROOT"/*|"$BIN") echo "run.sh: refusing OUTDIR $OUT" >&2; exit 2;; esac
if [ -n "$(ls -A "$OUT")" ]; then
    [ -f "$OUT/.regress-corpus" ] || { echo "run.sh: $OUT is not empty and not a corpus: refusing to clear it" >&2; exit 2; }
    find "$OUT" -mindepth 1 -delete
fi
touch "$OUT/.regress-corpus"
LOG=$OUT/log; O=$OUT/o; S=$OUT/scenes
mkdir -p "$LOG" "$O"
PFI=$BIN/pat-from-image; PI=$BIN/pat-info; PT=$BIN/pat-tile; P3=$BIN/polyfill3; SR=$BIN/scene-render
export BIN OUT O S ROOT PFI PI PT P3 SR
cd "$ROOT" || exit 2    # globs below expand here, relative to the repository
START=$(date +%s)
N=0; DUP=0
TO=${REGRESS_TIMEOUT:-120}   # seconds per command: a hang shows as exit status 124
CWD=$ROOT

echo "run.sh: generating inputs" >&2
python3 "$HERE/gen.py" "$ROOT" "$OUT" || echo "run.sh: gen.py failed" >&2

_rec() {  # NAME COMMAND-TEXT
    if [ -e "$LOG/$1.rc" ]; then echo "run.sh: duplicate name $1" >&2; DUP=$((DUP + 1)); fi
    N=$((N + 1))
    printf '%s\t%s\t%s\n' "$1" "$CWD" "$2" >>"$OUT/commands.tsv"
}
_done() { echo $? >"$LOG/$1.rc"; local t1=${EPOCHREALTIME/./}; echo "$1 $(( (t1 - T0) / 1000 )) ms" >>"$OUT/times.nocmp"; }
# r NAME CMD ARGS...            run in $CWD, stdin /dev/null
r() { local n=$1; shift; _rec "$n" "$*"; T0=${EPOCHREALTIME/./}
      ( cd "$CWD" && exec timeout -k 5 "$TO" "$@" ) </dev/null >"$LOG/$n.out" 2>"$LOG/$n.err"; _done "$n"; }
# ri NAME FILE CMD ARGS...      stdin from FILE
ri() { local n=$1 in=$2; shift 2; _rec "$n" "$* < $in"; T0=${EPOCHREALTIME/./}
       ( cd "$CWD" && exec timeout -k 5 "$TO" "$@" <"$in" ) >"$LOG/$n.out" 2>"$LOG/$n.err"; _done "$n"; }
# rp NAME 'SHELL PIPELINE'      bash -o pipefail -c
rp() { local n=$1; _rec "$n" "$2"; T0=${EPOCHREALTIME/./}
       ( cd "$CWD" && exec timeout -k 5 "$TO" bash -o pipefail -c "$2" ) </dev/null >"$LOG/$n.out" 2>"$LOG/$n.err"; _done "$n"; }
# mask NAME: stderr holds timing figures (--timings, polyfill3 --json "seconds"):
# keep the raw stderr as .err.nocmp, the figures masked as .err
mask() { mv "$LOG/$1.err" "$LOG/$1.err.nocmp"
         sed -E -e 's/[0-9]+(\.[0-9]+)?(e-?[0-9]+)? s\b/# s/g' -e 's/"seconds": ?[-+0-9.eE]+/"seconds":#/g' \
             "$LOG/$1.err.nocmp" >"$LOG/$1.err"; }
rt() { r "$@"; mask "$1"; }
rpt() { rp "$@"; mask "$1"; }

D2=(--perspective 55,1,0,1000 --lookat 0,100,-5,0,0,-900 --cull back)
BK=$ROOT/fixtures/patterns/bkgrnd.pat
TOOLS="pat-from-image pat-info pat-tile polyfill3 scene-render"

###########################################################################
echo "run.sh: help, version, usage" >&2
for t in $TOOLS; do
    r help-$t "$BIN/$t" --help
    r h-$t "$BIN/$t" -h
    r version-$t "$BIN/$t" --version
    r badflag-$t "$BIN/$t" --no-such-flag
    r missing-$t "$BIN/$t" no-such-file.input
done

###########################################################################
echo "run.sh: examples/Makefile" >&2
CWD=$ROOT/examples; M=$O/make; mkdir -p "$M/spin"
r make-marble.pat "$PFI" --size 64 --colors 16 --dither floyd-steinberg -o "$M/marble.pat" ../fixtures/images/marble.png
r make-marble-info "$PI" "$M/marble.pat"
r make-marble-wall "$PT" --size 1024x768 --scale 2 -o "$M/marble-wall.png" "$M/marble.pat"
r make-brick-wall "$PT" --size 1024x768 --scale 2 -o "$M/brick-wall.png" ../fixtures/patterns/brick.pat
r make-demo1 "$SR" --ortho2 0,1023,0,767 --background 255,255,255 -o "$M/demo1.png" scenes/demo1.json
r make-demo2.ndjson "$P3" -o "$M/demo2.ndjson" scenes/demo2.json
r make-demo2 "$SR" "${D2[@]}" --background-pattern ../fixtures/patterns/bkgrnd.pat -o "$M/demo2.png" "$M/demo2.ndjson"
r make-demo2-fig51.ndjson "$P3" -o "$M/demo2-fig51.ndjson" ../fixtures/scenes/demo2-fig51.json
r make-demo2-fig51 "$SR" "${D2[@]}" --background-pattern ../fixtures/patterns/bkgrnd.pat -o "$M/demo2-fig51.png" "$M/demo2-fig51.ndjson"
r make-demo2-spin.ndjson "$P3" -o "$M/demo2-spin.ndjson" ../fixtures/scenes/demo2-spin.json
for k in 0000 0007 0023 0035; do
    r make-spin-frame-$k "$SR" "${D2[@]}" --background-pattern ../fixtures/patterns/bkgrnd.pat \
        --frames 36 --frame $k -o "$M/spin/frame-$k.png" "$M/demo2-spin.ndjson"
done
r make-two-spheres "$SR" --ortho -80,80,-60,60,0,100 --size 800x600 -o "$M/two-spheres.png" ../fixtures/scenes/two-spheres.json
r make-turn "$SR" --ortho -80,80,-60,60,0,100 --size 400x300 --frames 36 --animate --fps 12 \
    -o "$M/turn.png" ../fixtures/scenes/two-spheres-turn.json
for d in demo1 demo2 two-spheres; do
    r make-check-$d "$SR" --image "$M/$d.png" --compare golden/$d.png
done
r make-check-demo2-fig51 "$SR" --image "$M/demo2-fig51.png" --compare golden/demo2.png
CWD=$ROOT

###########################################################################
echo "run.sh: fixtures/make-*.sh, docs/make-pictures.sh" >&2
F=$O/fixtures; mkdir -p "$F"
for spec in brick:64 wood:64 weave:32 mod:32 bkgrnd:64 pyr:64 chex:16 earth:64 moon:32; do
    name=${spec%%:*}; size=${spec##*:}
    r mkpat-$name "$PFI" --size "$size" --colors 16 --dither none -o "$F/$name.pat" "fixtures/images/$name.png"
done
r mkpat-check "$PI" --check fixtures/patterns/*.pat
r mkpat-check-regenerated "$PI" --check "$F"/*.pat
r mkstripes-check "$PI" --check fixtures/stripes/*.map
mkdir -p "$O/pictures"
for p in brick wood weave mod bkgrnd pyr chex; do
    r pictures-$p "$PT" --size 128x128 --scale 2 --background 255,255,255 -o "$O/pictures/$p.png" "fixtures/patterns/$p.pat"
done

###########################################################################
echo "run.sh: pat-info" >&2
for f in fixtures/patterns/*.pat; do
    n=$(basename "$f" .pat)
    r info-$n "$PI" "$f"
    r info-json-$n "$PI" --json "$f"
    r info-preview-$n "$PI" --preview "$f"
    r info-preview16-$n "$PI" --preview --preview-size 16 "$f"
    r info-at-$n "$PI" --at 3,5 "$f"
    r info-at-json-$n "$PI" --json --at 0,0 "$f"
    r info-at-far-$n "$PI" --at 15,15 "$f"
    r info-check-$n "$PI" --check "$f"
    ri info-stdin-$n "$f" "$PI" -
done
r info-all "$PI" fixtures/patterns/*.pat
r info-all-json "$PI" --json fixtures/patterns/*.pat
r info-all-preview "$PI" --preview fixtures/patterns/*.pat
rp info-all-check-valid "$PI --check fixtures/patterns/*.pat && echo valid"
rp info-readme-jq "$PI --json --at 3,5 fixtures/patterns/brick.pat | jq '.files[0].texel'"
rp info-help-jq "$PI --at 3,5 --json fixtures/patterns/brick.pat | jq '.files[0].texel'"
rp info-help-pipe "$PT --pat --size 256x256 fixtures/patterns/brick.pat | $PI -"
r info-generated-marble "$PI" "$O/make/marble.pat"
for f in fixtures/stripes/*.map; do
    n=$(basename "$f" .map)
    r info-map-$n "$PI" "$f"
    r info-map-json-$n "$PI" --json "$f"
    r info-map-preview-$n "$PI" --preview "$f"
done
r info-maps-json "$PI" --json fixtures/stripes/*.map
r info-maps-and-pats "$PI" fixtures/stripes/runway.map fixtures/patterns/chex.pat
r info-tm "$PI" fixtures/stripes/s-curve.tm
r info-ct "$PI" fixtures/stripes/terrain.ct
CWD=$S/t
r info-t-c "$PI" c.pat
ri info-t-json-stdin c.pat "$PI" --json --at 1,0 c.pat -
r info-t-at00 "$PI" --at 0,0 c.pat
r info-t-at016 "$PI" --at 0,16 c.pat
r info-t-at-neg "$PI" --at=-1,0 c.pat
r info-t-check-good "$PI" --check c.pat
r info-t-check-bad "$PI" --check bad.pat c.pat empty.pat missing.pat .
r info-t-bad-and-good "$PI" binary.pat c.pat
r info-t-bad2 "$PI" bad2.pat
r info-t-bad3 "$PI" bad3.pat
r info-t-bogus "$PI" --bogus
r info-t-at-x "$PI" --at x,1 a.pat
r info-t-check-json "$PI" --check --json a.pat
r info-t-preview-c "$PI" --preview c.pat
r info-t-preview-size0 "$PI" --preview --preview-size 0 c.pat
for n in p q b w half checker dots opaque c48 pt16 pt64 pt256 pt1024; do
    r info-t-$n "$PI" $n.pat
done
r info-t-pt1024-preview "$PI" --preview pt1024.pat
r info-t-pt1024-json "$PI" --json --at 1000,999 pt1024.pat
r info-t-map8 "$PI" m.map
r info-t-map8-json-mix "$PI" --json m.map c.pat
r info-t-map8-preview "$PI" --preview m.map
r info-t-badmaps "$PI" odd1000.map big.map
r info-t-map-at "$PI" --at 0,0 m.map
r info-t-tm "$PI" maps/s.tm
r info-t-record0 "$PI" --record 0 sscene.json
r info-t-record1-json "$PI" --record 1 --json sscene.json
r info-t-record0-json "$PI" --json --record 0 sscene.json
for i in 0 1 2 3 4 5 6; do r info-t-record-bad$i "$PI" --record 0 sbad$i.json; done
r info-t-record5 "$PI" --record 5 sscene2.json
r info-t-record-plain "$PI" --record 0 splain.json
r info-t-record-two-files "$PI" --record 0 sscene.json splain.json
CWD=$S/docs
for i in 0 1; do r info-docs-field-record$i "$PI" --record $i field.json; done
for i in 0 1 2 3; do r info-docs-schema-record$i "$PI" --record $i stripe-schema.json; done
r info-docs-schema-record2-json "$PI" --record 2 --json stripe-schema.json
r info-docs-edit-record0 "$PI" --record 0 stripe-edit.json
CWD=$ROOT

###########################################################################
echo "run.sh: pat-tile" >&2
T=$O/tile; mkdir -p "$T"
for f in fixtures/patterns/*.pat; do
    n=$(basename "$f" .pat)
    r tile-$n "$PT" --size 256x192 -o "$T/$n.png" "$f"
    r tile-scale-$n "$PT" --size 200x150 --scale 3 --offset -5,7 -o "$T/$n-s3.png" "$f"
    r tile-ppm-$n "$PT" --size 64x48 --background 255,255,255 -o "$T/$n.ppm" "$f"
    r tile-pam-$n "$PT" --size 50x40 -o "$T/$n.pam" "$f"
    r tile-pat-$n "$PT" --pat --size 128x128 --offset 3,5 -o "$T/$n-128.pat" "$f"
    r tile-stdout-ppm-$n "$PT" --size 32x32 --format ppm "$f"
    r tile-bg-hex-$n "$PT" --size 70x30 --scale 2 --background '#102030' --format pam -o "$T/$n-bg.pam" "$f"
done
r tile-readme-wall "$PT" --size 1024x768 --scale 2 -o "$T/wall.png" fixtures/patterns/brick.pat
r tile-readme-ppm "$PT" --size 640x480 --format ppm --background 255,255,255 fixtures/patterns/weave.pat
r tile-readme-chex256 "$PT" --pat --size 256x256 fixtures/patterns/chex.pat -o "$T/chex256.pat"
r tile-help-wall "$PT" --size 1024x768 -o "$T/help-wall.png" fixtures/patterns/brick.pat
r tile-help-big "$PT" --size 256x256 --scale 4 --background 255,255,255 fixtures/patterns/brick.pat
r tile-help-view "$PT" --size 640x480 --format ppm fixtures/patterns/brick.pat
r tile-help-brick256 "$PT" --pat --size 256x256 fixtures/patterns/brick.pat -o "$T/brick256.pat"
r tile-default-size "$PT" fixtures/patterns/mod.pat
ri tile-stdin fixtures/patterns/weave.pat "$PT" --size 40x40 --format pam -
r tile-bench-in-png "$PT" --size 64x64 -o "$T/bench-in.png" fixtures/patterns/brick.pat
r tile-bench-in-ppm "$PT" --size 64x64 -o "$T/bench-in.ppm" fixtures/patterns/brick.pat
r tile-bench-4096-png "$PT" --size 4096x4096 -o "$T/bench-4096.png" fixtures/patterns/brick.pat
rp tile-bench-4096-ppm-sha "$PT --size 4096x4096 -o - --format ppm fixtures/patterns/brick.pat | sha256sum"
r tile-pat-4096 "$PT" --pat --size 4096x4096 -o "$T/chex4096.pat" fixtures/patterns/chex.pat
CWD=$S/t
r tile-t-20x18 "$PT" --size 20x18 -o "$T/t-20x18.png" c.pat
r tile-t-scale-offset-bg "$PT" --size 8x8 --scale 4 --offset -1,0 --background '#102030' --format ppm c.pat
r tile-t-ppm-warn "$PT" --size 4x4 -o "$T/t-x.ppm" c.pat
r tile-t-pam-alpha "$PT" --size 3x2 -o "$T/t-x.pam" c.pat
r tile-t-direct "$PT" --size 100x70 --scale 2 --offset 3,5 --format pam c.pat
r tile-t-big-pat "$PT" --pat --size 64x64 --scale 2 --offset 3,5 -o "$T/t-big.pat" c.pat
r tile-t-via-pat "$PT" --size 100x70 --format pam "$T/t-big.pat"
r tile-t-bad "$PT" --size 8x8 -o "$T/t-bad.png" bad2.pat
r tile-t-missing "$PT" --size 8x8 -o "$T/t-missing.png" missing.pat
for s in 0x5 100000x10 60000x60000 12 axb; do r tile-t-size-$s "$PT" --size $s c.pat; done
r tile-t-pat-nonsquare "$PT" --pat --size 64x32 c.pat
r tile-t-pat-not16 "$PT" --pat --size 40x40 c.pat
r tile-t-jpg "$PT" -o "$T/t-x.jpg" c.pat
r tile-t-format-bad "$PT" --format gif --size 4x4 c.pat
r tile-t-scale0 "$PT" --scale 0 --size 4x4 c.pat
r tile-t-bg-bad "$PT" --background 1,2 --size 4x4 c.pat
rp tile-t-closed-pipe "$PT --size 4096x4096 --format ppm --background 0,0,0 c.pat | head -c 100"
for n in p q b w checker dots opaque c48 pt1024; do
    r tile-t-$n "$PT" --size 96x64 --scale 2 -o "$T/t-$n.png" $n.pat
done
CWD=$ROOT

###########################################################################
echo "run.sh: pat-from-image" >&2
P=$O/pfi; mkdir -p "$P"
for f in fixtures/images/*.png; do
    n=$(basename "$f" .png)
    r pfi-$n "$PFI" -o "$P/$n.pat" "$f"
    r pfi-fs-$n "$PFI" --size 32 --colors 8 --dither floyd-steinberg -o "$P/$n-fs.pat" "$f"
    r pfi-ordered-$n "$PFI" --size 48 --colors 4 --dither ordered --report -o "$P/$n-ord.pat" "$f"
    r pfi-crop-$n "$PFI" --crop --size 16 --colors 256 "$f"
    r pfi-palette-$n "$PFI" --size 32 --palette fixtures/patterns/brick.pat --dither ordered -o "$P/$n-pal.pat" "$f"
    r pfi-transparent-$n "$PFI" --size 16 --colors 6 --transparent 0,0,0 --alpha-threshold 200 "$f"
    r pfi-alpha0-$n "$PFI" --size 16 --alpha-threshold 0 "$f"
    r pfi-enlarge-$n "$PFI" --size 128 --colors 32 --dither floyd-steinberg --report -o "$P/$n-128.pat" "$f"
    r pfi-stripe90-$n "$PFI" --stripe --angle 90 --length 64 "$f"
    r pfi-stripe-$n "$PFI" --stripe -o "$P/$n.map" "$f"
    r pfi-stripe30-$n "$PFI" --stripe --angle 30 --length 16 "$f"
done
r pfi-readme-marble "$PFI" --size 64 --colors 16 -o "$P/readme-marble.pat" fixtures/images/marble.png
rp pfi-readme-palette "$PFI --size 32 --palette fixtures/patterns/brick.pat --dither ordered fixtures/images/marble.png > '$P/readme-p.pat'"
r pfi-help-default "$PFI" fixtures/images/brick.png -o "$P/help-brick.pat"
rp pfi-help-leaf "$PFI --size 32 --colors 8 --dither floyd-steinberg fixtures/images/wood.png > '$P/help-leaf.pat'"
ri pfi-help-stdin-report fixtures/images/marble.png "$PFI" --report -o "$P/help-rose.pat"
ri pfi-stdin-default fixtures/images/chex.png "$PFI" --size 16
r pfi-colors1 "$PFI" --colors 1 --size 16 fixtures/images/marble.png
r pfi-colors256 "$PFI" --colors 256 --size 256 --report fixtures/images/marble.png -o "$P/marble-256.pat"
r pfi-size4096 "$PFI" --size 1024 --colors 8 -o "$P/marble-1024.pat" fixtures/images/marble.png
r pfi-palette-pat-self "$PFI" --palette "$P/marble.pat" --size 64 --dither floyd-steinberg -o "$P/marble-repal.pat" fixtures/images/marble.png
# PNM / PAM input (pat-tile writes them)
r pfi-make-ppm "$PT" --size 64x64 --background 255,255,255 -o "$P/weave.ppm" fixtures/patterns/weave.pat
r pfi-make-pam "$PT" --size 64x64 -o "$P/weave.pam" fixtures/patterns/weave.pat
r pfi-from-ppm "$PFI" --size 32 --colors 16 "$P/weave.ppm"
r pfi-from-pam "$PFI" --size 32 --colors 16 "$P/weave.pam"
# every fixture through pat-tile then pat-from-image (pat_from_image.rs)
for spec in brick:64 wood:64 weave:32 mod:32 bkgrnd:64 pyr:64 chex:16 earth:64 moon:32; do
    name=${spec%%:*}; size=${spec##*:}
    rp pfi-roundtrip-$name "$PT --size ${size}x$size --scale 1 --format png fixtures/patterns/$name.pat | $PFI --size $size --colors 256 -"
done
# bench/pat_from_image.sh's matrix (ImageMagick's images replaced by generated ones)
CWD=$S/img
for img in gradient radial plasma drawing noise; do
    for n in 64 256; do
        for k in 4 8 16 32; do
            r pfi-bench-$img-$n-$k "$PFI" --size $n --colors $k -o "$P/bench-$img-$n-$k.pat" $img-$n.png
        done
    done
done
for n in 64 256; do
    r pfi-bench-alpha-$n "$PFI" --size 64 --report alpha-$n.png
    r pfi-bench-alpha-fs-$n "$PFI" --size 64 --dither floyd-steinberg --alpha-threshold 64 alpha-$n.png
done
CWD=$S/t
r pfi-t-roundtrip "$PFI" --size 32 --colors 4 -o "$P/t-out.pat" in.png
r pfi-t-crop "$PFI" --crop --size 16 --colors 256 wide.png
r pfi-t-file "$PFI" --size 32 in.png
ri pfi-t-stdin in.png "$PFI" --size 32 -
ri pfi-t-stdin-default in.png "$PFI" --size 32
r pfi-t-palette-list "$PFI" --size 16 --palette pal.txt -o "$P/t-pal.pat" in.png
r pfi-t-palette-pat "$PFI" --size 16 --dither floyd-steinberg --palette "$P/t-pal.pat" -o "$P/t-pal2.pat" in.png
r pfi-t-transparent "$PFI" --size 32 --transparent '#00a000' in.png
r pfi-t-alpha0 "$PFI" --size 32 --alpha-threshold 0 in.png
for dither in none floyd-steinberg ordered; do
    for size in 16 128; do
        r pfi-t-grad-$dither-$size "$PFI" --report --colors 8 --size $size --dither $dither grad.png
    done
done
r pfi-t-ega "$PFI" --palette ega.txt --transparent 255,0,255 icon.png -o "$P/t-icon.pat"
r pfi-t-ega-crop "$PFI" --crop --size 16 icon.png -o "$P/t-sprite.pat"
# failures (pat_from_image.rs bad_inputs...): status, message, no output left
E=$O/pfi-err; mkdir -p "$E"
r pfi-err-missing "$PFI" missing.png -o "$E/o1.pat"
r pfi-err-dir "$PFI" . -o "$E/o2.pat"
r pfi-err-junk "$PFI" junk.png -o "$E/o3.pat"
ri pfi-err-stdin-junk junk.png "$PFI" - -o "$E/o4.pat"
ri pfi-err-stdin-empty empty.pat "$PFI" - -o "$E/o5.pat"
for size in 0 17 8192 abc; do r pfi-err-size-$size "$PFI" --size $size in.png -o "$E/o.pat"; done
for k in 0 1000; do r pfi-err-colors-$k "$PFI" --colors $k in.png -o "$E/o.pat"; done
r pfi-err-transparent-red "$PFI" --transparent red in.png -o "$E/o.pat"
r pfi-err-transparent-12 "$PFI" --transparent 1,2 in.png -o "$E/o.pat"
r pfi-err-dither "$PFI" --dither lots in.png -o "$E/o.pat"
r pfi-err-alpha "$PFI" --alpha-threshold 300 in.png -o "$E/o.pat"
r pfi-err-crop-small "$PFI" --crop --size 64 in.png -o "$E/o.pat"
r pfi-err-nopal "$PFI" --palette nopal.txt in.png -o "$E/o.pat"
r pfi-err-pal-png "$PFI" --palette in.png in.png -o "$E/o.pat"
r pfi-err-pal-colors "$PFI" --colors 4 --palette x in.png -o "$E/o.pat"
r pfi-err-badpal "$PFI" --palette badpal.txt in.png -o "$E/o.pat"
r pfi-t-stripe-bars "$PFI" --stripe --length 8 bars.png -o "$P/t-bars.map"
r pfi-t-stripe-bars90 "$PFI" --stripe --angle 90 --length 4 bars.png
r pfi-t-stripe-info "$PI" "$P/t-bars.map"
r pfi-err-stripe-length "$PFI" --stripe --length 1000 bars.png -o "$E/x.map"
r pfi-err-angle-nostripe "$PFI" --angle 10 bars.png -o "$E/x.map"
r pfi-err-stripe-colors "$PFI" --stripe --colors 4 bars.png -o "$E/x.map"
r pfi-err-stripe-junk "$PFI" --stripe junk.png -o "$E/x.map"
rp pfi-err-leftovers "ls -A '$E'"
CWD=$S/docs
r pfi-docs-field-map "$PFI" --stripe --angle 90 --length 1024 field.png -o "$P/field.map"
r pfi-help-furrow "$PFI" --stripe --angle 90 --length 512 field.png -o "$P/furrow.map"
CWD=$ROOT

###########################################################################
echo "run.sh: polyfill3" >&2
Q=$O/p3; mkdir -p "$Q"
for f in fixtures/scenes/*.json examples/scenes/*.json; do
    n=$(basename "$f" .json)
    r p3-$n "$P3" -o "$Q/$n.ndjson" "$f"
    r p3-merge-$n "$P3" --merge -o "$Q/$n-merge.ndjson" "$f"
    r p3-uv-$n "$P3" --uv -o "$Q/$n-uv.ndjson" "$f"
    rt p3-json-$n "$P3" --json "$f"
    r p3-thesis-$n "$P3" --compat thesis -o "$Q/$n-thesis.ndjson" "$f"
    r p3-cull-$n "$P3" --camera "$S/docs/cam.json" --cull -o "$Q/$n-cull.ndjson" "$f"
    r p3-merge-cull-$n "$P3" --merge --camera "$S/docs/cam.json" --cull -o "$Q/$n-merge-cull.ndjson" "$f"
    r p3-uv-cull-$n "$P3" --uv --camera "$S/docs/cam.json" --cull -o "$Q/$n-uv-cull.ndjson" "$f"
    r p3-tol-$n "$P3" --tolerance 0.5 --uv "$f"
done
r p3-readme-faces "$P3" fixtures/scenes/demo2-faces.json -o "$Q/pyramid.json"
rp p3-readme-thesis-wc "$P3 --compat thesis fixtures/scenes/demo2-plain.json | wc -l"
rp p3-readme-plain-wc "$P3 fixtures/scenes/demo2-plain.json | wc -l"
rp p3-thesis-faces-wc "$P3 --compat thesis fixtures/scenes/demo2-faces.json | wc -l"
rp p3-help-thesis-wc "$P3 --compat thesis --incr 25 fixtures/scenes/demo2-plain.json | wc -l"
rp p3-readme-merge-render "$P3 --merge --camera $S/docs/cam.json --cull examples/scenes/demo2.json | $SR -o '$Q/merge-cull.png' -"
rp p3-help-merge-render "$P3 --merge examples/scenes/demo2.json | $SR ${D2[*]} -o '$Q/merge.png' -"
rp p3-help-uv-render "$P3 --uv examples/scenes/demo2.json | $SR ${D2[*]} -o '$Q/uv.png' -"
rp p3-readme-uv "$P3 --uv fixtures/scenes/demo2-fig51.json > '$Q/uv.json'"
ri p3-stdin-relative fixtures/scenes/demo2-plain.json "$P3"
CWD=$ROOT/fixtures/scenes
ri p3-stdin-in-scenes demo2-plain.json "$P3"
CWD=$S/docs
r p3-readme-pattern-defaults "$P3" --pattern "$ROOT/fixtures/patterns/brick.pat" --incr 2 --horz -5 faces.json -o "$Q/faces-brick.ndjson"
r p3-faces-rotate "$P3" --pattern "$ROOT/fixtures/patterns/pyr.pat" --incr 3 --rotate 30 --vert 2.5 faces.json -o "$Q/faces-rot.ndjson"
r p3-faces-merge "$P3" --pattern "$ROOT/fixtures/patterns/weave.pat" --incr 4 --horz 0.5 --merge faces.json -o "$Q/faces-merge.ndjson"
r p3-faces-thesis "$P3" --pattern "$ROOT/fixtures/patterns/pyr.pat" --incr 2 --horz -5 --compat thesis faces.json -o "$Q/faces-thesis.ndjson"
r p3-faces-nopattern "$P3" faces.json
r p3-face-instance "$P3" face-instance.json
r p3-readme-face "$P3" --pattern "$ROOT/fixtures/patterns/chex.pat" readme-face.json
r p3-readme-sphere "$P3" readme-sphere.json -o "$Q/readme-sphere.ndjson"
r p3-readme-sphere-tol "$P3" --tolerance 1 readme-sphere.json
r p3-quadrics "$P3" quadrics.json -o "$Q/quadrics.ndjson"
r p3-quadrics-tol "$P3" --tolerance 0.5 quadrics.json -o "$Q/quadrics-tol.ndjson"
r p3-transforms "$P3" transforms.json -o "$Q/transforms.ndjson"
r p3-transforms-uv "$P3" --uv transforms.json -o "$Q/transforms-uv.ndjson"
r p3-cube "$P3" cube.json -o "$Q/cube.ndjson"
r p3-cube-cull-textbook "$P3" --camera textbook-cam.json --cull cube.json
r p3-shapes "$P3" shapes.json
r p3-shapes-uv "$P3" --uv --tolerance 0.1 shapes.json
r p3-field "$P3" field.json
CWD=$S/t
ri p3-t-passthrough passthrough.json "$P3"
r p3-t-sq "$P3" sq.json
ri p3-t-twod twod.json "$P3" --pattern p1.pat --incr 10
r p3-t-merge-plain "$P3" merge.json
r p3-t-merge "$P3" --merge merge.json
r p3-t-cull-plain "$P3" --camera cam.json --cull "$ROOT/fixtures/scenes/demo2-plain.json"
r p3-t-cull-under "$P3" --camera cam.json --cull under.json
r p3-t-camera-nocull "$P3" --camera cam.json under.json
r p3-t-cull-nocamera "$P3" --cull under.json
rt p3-t-json-summary "$P3" --json tri-rect.json
r p3-t-rotate45 "$P3" --rotate 45 tri-rect.json
r p3-t-thesis-fraction "$P3" --compat thesis --horz 0.5 tri-rect.json
for i in 0 1 2 3 4 5 6 7 8; do ri p3-t-bad$i p3bad$i.json "$P3" --max-polygons 1000000; done
ri p3-t-nonplanar-default p3bad2.json "$P3"
r p3-t-planarity-loose "$P3" --planarity-tol 0.5 p3bad2.json
ri p3-t-incr0 p3ok.json "$P3" --incr 0
ri p3-t-incr-neg p3ok.json "$P3" --incr -1
ri p3-t-fail-no-output p3bad1.json "$P3" -o "$Q/t-fail.json"
for i in 0 1 2 3 4; do r p3-t-objbad$i "$P3" objbad$i.json -o "$Q/t-objbad.json"; done
r p3-t-ball "$P3" ball.json -o "$S/t/cells-ball.ndjson"
r p3-t-ball-maxpoly "$P3" --max-polygons 60 ball.json
r p3-t-qspin "$P3" qspin.json
for i in 0 1 2 3 4 5 6 7 8 9 10 11; do r p3-t-qbad$i "$P3" qbad$i.json; done
r p3-t-texuv "$P3" --uv texuv.json -o "$Q/t-texuv.ndjson"
r p3-t-tex "$P3" tex.json -o "$Q/t-tex.ndjson"
r p3-t-aligned "$P3" aligned.json -o "$Q/t-aligned.ndjson"
r p3-t-uvrecs "$P3" --uv --tolerance 0.1 uvrecs.json
r p3-t-uv-merge "$P3" --uv --merge uvrecs.json
r p3-t-uv-compat "$P3" --uv --compat thesis uvrecs.json
for e in -6 -2 0 6; do r p3-t-incr1e$e "$P3" st-incr1e$e.json; done
for i in 0 1; do r p3-t-fine$i "$P3" st-fine$i.json -o "$Q/t-out.pam"; done
for i in 0 1 2 3; do r p3-t-shift$i "$P3" st-shift$i.json; done
for i in 0 1 2 3 4 5 6; do r p3-t-json$i "$P3" st-json$i.json -o "$Q/t-out.pam"; done
r p3-t-huge3 "$P3" st-huge3.json -o "$Q/t-out.pam"
r p3-t-st-t1e7 "$P3" st-t1e7.json
r p3-t-st-s1e9 "$P3" st-s1e9.json
r p3-t-st-floor "$P3" st-floor.json
rp p3-t-closed-pipe "$P3 --incr 0.01 --pattern brick.pat $ROOT/fixtures/scenes/demo2-plain.json | head -c 100"
CWD=$ROOT

###########################################################################
echo "run.sh: scene-render, docs and help examples" >&2
R=$O/sr; mkdir -p "$R"
CWD=$S/docs
r sr-readme-shapes "$SR" --background 255,255,255 shapes.json -o "$R/shapes.png"
r sr-readme-demo2-direct "$SR" --perspective 55,1,0,1000 --lookat 0,100,-5,0,0,-900 \
    --cull back --background-pattern "$BK" "$ROOT/examples/scenes/demo2.json" -o "$R/demo2-direct.png"
r sr-readme-reference "$SR" --reference shapes.json -o "$R/shapes-ref.png"
r sr-readme-reference-json "$SR" --reference --json --size 512x384 shapes.json -o "$R/shapes-ref2.png"
r sr-readme-ss16-compare "$SR" --aa ss16 shapes.json --compare "$R/shapes-ref.png" --diff "$R/shapes-diff.png"
r sr-readme-compare-json "$SR" --image "$R/shapes.png" --compare "$R/shapes-ref.png" --json
r sr-compare-text "$SR" --image "$R/shapes.png" --compare "$R/shapes-ref.png"
r sr-compare-diff-out "$SR" --aa none shapes.json -o "$R/shapes-none.png" --compare "$R/shapes-ref.png" --diff "$R/shapes-none-diff.png"
r sr-compare-to-stdout-image "$SR" --aa ss4 shapes.json -o - --compare "$R/shapes-ref.png"
FV=(--perspective 50,1.333,1,3000 --lookat 0,8,10,0,4,-100)
r sr-readme-field "$SR" "${FV[@]}" field.json -o "$R/field.png"
r sr-readme-field-nearest "$SR" --stripe-lod nearest field.json -o "$R/field-nearest-nocam.png"
r sr-readme-field-cig "$SR" --cig-compat field.json -o "$R/field-cig-nocam.png"
r sr-readme-field-ref "$SR" --reference field.json -o "$R/field-ref-nocam.png"
r sr-docs-field-nearest "$SR" "${FV[@]}" --stripe-lod nearest field.json -o "$R/field-nearest.png"
r sr-docs-field-blended "$SR" "${FV[@]}" --stripe-lod blended field.json -o "$R/field-blended.png"
r sr-docs-field-cig "$SR" "${FV[@]}" --cig-compat field.json -o "$R/field-cig.png"
r sr-docs-field-ref "$SR" "${FV[@]}" --reference --json field.json -o "$R/field-ref.png"
r sr-docs-field-compare "$SR" "${FV[@]}" field.json --compare "$R/field-ref.png" --diff "$R/field-diff.png"
for aa in none ss4 ss16 exact; do
    r sr-docs-field-$aa "$SR" "${FV[@]}" --aa $aa --size 320x240 field.json -o "$R/field-$aa.png"
    r sr-docs-field-cig-$aa "$SR" "${FV[@]}" --aa $aa --cig-compat --size 320x240 field.json -o "$R/field-cig-$aa.png"
    r sr-docs-field-nearest-$aa "$SR" "${FV[@]}" --aa $aa --stripe-lod nearest --size 320x240 field.json -o "$R/field-nearest-$aa.png"
    r sr-docs-schema-$aa "$SR" --perspective 60,1.333,1,500 --lookat 0,15,20,0,0,-50 --aa $aa --size 320x240 stripe-schema.json -o "$R/schema-$aa.png"
done
r sr-docs-schema-ref "$SR" --perspective 60,1.333,1,500 --lookat 0,15,20,0,0,-50 --reference --size 320x240 stripe-schema.json -o "$R/schema-ref.png"
r sr-docs-schema-threads1 "$SR" --perspective 60,1.333,1,500 --lookat 0,15,20,0,0,-50 --threads 1 --size 320x240 stripe-schema.json -o "$R/schema-t1.png"
r sr-docs-field-frames "$SR" "${FV[@]}" --size 160x120 --frames 2 field.json -o "$R/field-f%d.png"
# docs/camera.md
r sr-camera-iris-flags "$SR" --lookat 0,100,-5,0,0,-900 --perspective 55,1,0,1000 "$ROOT/examples/scenes/demo2.json" -o "$R/cam-iris.png"
r sr-camera-iris-file "$SR" --camera cam.json "$ROOT/examples/scenes/demo2.json" -o "$R/cam-iris-file.png"
ri sr-camera-stdin cam.json "$SR" --camera - --size 256x192 "$ROOT/examples/scenes/demo2.json" -o "$R/cam-stdin.png"
r sr-camera-oblique-cabinet "$SR" --window -2,2,-2,2 --oblique cabinet,30 --front -10 --back 10 cube.json -o "$R/cam-cabinet.png"
r sr-camera-oblique-cavalier "$SR" --window -2,2,-2,2 --oblique cavalier --front -10 --back 10 --size 320x240 cube.json -o "$R/cam-cavalier.png"
r sr-camera-isometric "$SR" --window -2,2,-2,2 --oblique isometric --front -10 --back 10 --size 320x240 cube.json -o "$R/cam-iso.png"
r sr-camera-textbook-file "$SR" --camera textbook-cam.json --size 320x240 cube.json -o "$R/cam-textbook.png"
r sr-camera-textbook-flags "$SR" --vrp 0,0,0 --vpn 0,0,-1 --view-up 0,1,0 --view-distance 0 --window -1,1,-1,1 \
    --cop 0,0,2 --front 0 --back 10 --size 320x240 cube.json -o "$R/cam-textbook-flags.png"
r sr-camera-textbook-dop "$SR" --vrp 1,1,1 --vpn -1,-1,-1 --window -2,2,-1.5,1.5 --dop -1,-1.2,-1 --front 0 --back 20 --size 320x240 cube.json -o "$R/cam-dop.png"
r sr-camera-textbook-offaxis "$SR" --vrp 0,0,0 --vpn 0,0,-1 --window -1,1,-1,1 --cop 0.5,0.3,2 --front 0 --back 10 --size 320x240 cube.json -o "$R/cam-offaxis.png"
r sr-camera-up-twist "$SR" --lookat 0,2,3,0,0,-1.5 --up 0.3,1,0 --twist 15 --perspective 60,1.333,0.1,50 --size 320x240 cube.json -o "$R/cam-twist.png"
r sr-camera-ortho "$SR" --ortho -3,3,-2.25,2.25,0,20 --size 320x240 cube.json -o "$R/cam-ortho.png"
r sr-camera-ortho2 "$SR" --ortho2 -3,3,-2.25,2.25 --size 320x240 cube.json -o "$R/cam-ortho2.png"
r sr-camera-default "$SR" --size 320x240 cube.json -o "$R/cam-default.png"
r sr-camera-err-both "$SR" --camera cam.json --ortho2 0,1,0,1 cube.json -o "$R/x.png"
r sr-camera-err-vpn0 "$SR" --window -1,1,-1,1 --vpn 0,0,0 --cop 0,0,2 --front 0 --back 10 cube.json -o "$R/x.png"
r sr-camera-err-upvpn "$SR" --window -1,1,-1,1 --view-up 0,0,-1 --cop 0,0,2 --front 0 --back 10 cube.json -o "$R/x.png"
r sr-camera-err-cop-behind "$SR" --window -1,1,-1,1 --cop 0,0,-2 --front 0 --back 10 cube.json -o "$R/x.png"
r sr-camera-err-front-back "$SR" --window -1,1,-1,1 --cop 0,0,2 --front 5 --back 1 cube.json -o "$R/x.png"
r sr-camera-err-dop-parallel "$SR" --window -1,1,-1,1 --dop 1,0,0 --front 0 --back 10 cube.json -o "$R/x.png"
r sr-camera-err-two-proj "$SR" --window -1,1,-1,1 --dop 0,0,-1 --cop 0,0,2 --front 0 --back 10 cube.json -o "$R/x.png"
r sr-camera-err-nowindow "$SR" --cop 0,0,2 --front 0 --back 10 cube.json -o "$R/x.png"
r sr-camera-err-eye-center "$SR" --lookat 1,1,1,1,1,1 --perspective 60,1,0.1,10 cube.json -o "$R/x.png"
r sr-camera-err-fovy "$SR" --perspective 180,1,0.1,10 cube.json -o "$R/x.png"
r sr-camera-err-aspect "$SR" --perspective 60,0,0.1,10 cube.json -o "$R/x.png"
r sr-camera-err-far "$SR" --perspective 60,1,10,1 cube.json -o "$R/x.png"
r sr-camera-err-near-neg "$SR" --perspective 60,1,-1,10 cube.json -o "$R/x.png"
r sr-camera-err-ortho0 "$SR" --ortho 0,0,0,1,0,1 cube.json -o "$R/x.png"
r sr-camera-err-oblique "$SR" --window -1,1,-1,1 --oblique weird --front 0 --back 1 cube.json -o "$R/x.png"
r sr-camera-err-lookat-short "$SR" --lookat 1,2,3 --perspective 60,1,0.1,10 cube.json -o "$R/x.png"
r sr-camera-err-nan "$SR" --perspective NaN,1,0.1,10 cube.json -o "$R/x.png"
r sr-camera-err-missing-file "$SR" --camera nocam.json cube.json -o "$R/x.png"
r sr-camera-err-file-as-camera "$SR" --camera shapes.json cube.json -o "$R/x.png"
# docs/objects.md and README objects, instances, quadrics
r sr-objects-face-instance "$SR" "${D2[@]}" --size 320x240 face-instance.json -o "$R/face-instance.png"
r sr-objects-transforms "$SR" --ortho2 0,110,0,90 --size 440x360 transforms.json -o "$R/transforms.png"
r sr-objects-transforms-frames "$SR" --ortho2 0,110,0,90 --size 220x180 --frames 3 transforms.json -o "$R/transforms-%02d.png"
r sr-objects-quadrics "$SR" --ortho -80,80,-60,60,-100,100 --size 400x300 quadrics.json -o "$R/quadrics.png"
r sr-objects-quadrics-persp "$SR" --perspective 50,1.333,1,500 --lookat 0,30,120,0,0,-20 --size 400x300 quadrics.json -o "$R/quadrics-persp.png"
r sr-objects-quadrics-tol "$SR" --ortho -80,80,-60,60,-100,100 --size 400x300 --quadric-tolerance 2 quadrics.json -o "$R/quadrics-tol2.png"
r sr-objects-quadrics-expanded "$SR" --ortho -80,80,-60,60,-100,100 --size 400x300 "$Q/quadrics.ndjson" -o "$R/quadrics-expanded.png"
r sr-readme-sphere "$SR" --ortho -80,80,-60,60,0,100 --size 400x300 readme-sphere.json -o "$R/readme-sphere.png"
r sr-readme-animate-turn "$SR" --frames 36 --animate --size 256x192 -o "$R/readme-turn.png" "$ROOT/fixtures/scenes/two-spheres-turn.json"
# help examples
r sr-help-demo1 "$SR" --size 1024x768 --background 255,255,255 "$ROOT/examples/scenes/demo1.json" -o "$R/help-demo1.png"
rp sr-help-pipe-camera "$P3 $ROOT/fixtures/scenes/demo2-fig51.json | $SR --camera demo2.camera.json -o '$R/help-demo2.png'"
rp sr-help-stdout "$SR --perspective 55,1.333,0,1000 --lookat 0,100,-5,0,0,-900 $ROOT/examples/scenes/demo2.json > '$R/help-out.png'"
r sr-help-ss16-cull "$SR" --aa ss16 --cull back "${D2[@]:0:4}" "$ROOT/examples/scenes/demo2.json" -o "$R/help-ss16.png"
r sr-help-cull-front "$SR" --cull front "${D2[@]:0:4}" --size 320x240 "$ROOT/examples/scenes/demo2.json" -o "$R/help-cull-front.png"
r sr-help-cull-none "$SR" --cull none "${D2[@]:0:4}" --size 320x240 "$ROOT/examples/scenes/demo2.json" -o "$R/help-cull-none.png"
r sr-help-two "$SR" --ortho -80,80,-60,60,0,100 --size 800x600 "$ROOT/fixtures/scenes/two-spheres.json" -o "$R/help-two.png"
CWD=$ROOT

###########################################################################
echo "run.sh: scene-render matrix (aa, formats, threads, frames)" >&2
A=$O/aa; mkdir -p "$A"
# scene|flags (camera etc.)
# name|scene|flags|reference (the 80x80-slice spheres' reference takes minutes: left out)
MATRIX=(
  "demo1|examples/scenes/demo1.json|--ortho2 0,1023,0,767 --background 255,255,255 --size 512x384|ref"
  "demo2-direct|examples/scenes/demo2.json|${D2[*]} --background-pattern $BK --size 512x384|ref"
  "demo2-cells|$O/make/demo2.ndjson|${D2[*]} --background-pattern $BK --size 512x384|ref"
  "demo2-merged|$Q/demo2-merge.ndjson|${D2[*]} --size 512x384|ref"
  "demo2-uv|$Q/demo2-uv.ndjson|${D2[*]} --size 512x384|ref"
  "fig51|fixtures/scenes/demo2-fig51.json|${D2[*]} --size 512x384|ref"
  "two-spheres|fixtures/scenes/two-spheres.json|--ortho -80,80,-60,60,0,100 --size 400x300|"
  "seam|$S/t/seam.json|--ortho 0,200,0,200,-100,100 --size 200x200|ref"
  "tex|$S/t/tex.json|--perspective 60,1.333,0.1,100 --lookat 0,0.5,1,0,-0.5,-5 --size 96x72|ref"
  "texuv|$S/t/texuv.json|--perspective 60,1.333,0.1,100 --lookat 0,0.5,1,0,-0.5,-5 --size 96x72|ref"
  "curves|$S/t/curves.json|--size 40x30|ref"
  "tris200|$S/t/tris200.json|--size 100x70|ref"
  "spersp|$S/t/spersp.json|--size 160x120 --perspective 50,1.333,1,3000 --lookat 0,8,10,0,4,-100|ref"
)
for spec in "${MATRIX[@]}"; do
    IFS='|' read -r name scene flags ref <<<"$spec"
    # shellcheck disable=SC2086
    for aa in none ss1 ss4 ss9 ss16 ss64 exact; do
        r aa-$name-$aa "$SR" $flags --aa $aa "$scene" -o "$A/$name-$aa.png"
    done
    if [ -n "$ref" ]; then
        r aa-$name-reference "$SR" $flags --reference --json "$scene" -o "$A/$name-ref.png"
        r aa-$name-reference-s6 "$SR" $flags --reference --reference-samples 6 "$scene" -o "$A/$name-ref6.png"
        r aa-$name-compare "$SR" $flags "$scene" --compare "$A/$name-ref.png" --json --diff "$A/$name-diff.png"
        r aa-$name-compare-none "$SR" --image "$A/$name-none.png" --compare "$A/$name-ref.png"
    else
        r aa-$name-compare-none "$SR" --image "$A/$name-none.png" --compare "$A/$name-exact.png"
    fi
    r aa-$name-ppm "$SR" $flags --aa ss4 "$scene" -o "$A/$name.ppm"
    r aa-$name-pam "$SR" $flags "$scene" -o "$A/$name.pam"
    r aa-$name-format-ppm-stdout "$SR" $flags --format ppm "$scene"
    r aa-$name-threads1 "$SR" $flags --threads 1 "$scene" -o "$A/$name-t1.png"
    r aa-$name-threads3 "$SR" $flags --threads 3 --aa ss4 "$scene" -o "$A/$name-t3.png"
    rt aa-$name-timings "$SR" $flags --timings "$scene" -o "$A/$name-timed.png"
done
CWD=$S/t
r sr-t-half-png "$SR" --size 2x1 half.json -o "$A/t-half.png"
ri sr-t-half-ppm-stdin half.json "$SR" --size 2x1 --format ppm
r sr-t-half-pam "$SR" --size 2x1 half.json -o "$A/t-half.pam"
r sr-t-curves-ref "$SR" --size 40x30 --reference curves.json -o "$A/t-curves-ref.png"
r sr-t-curves-compare "$SR" --size 40x30 curves.json --compare "$A/t-curves-ref.png" --json
r sr-t-curves-none "$SR" --size 40x30 --aa none curves.json -o "$A/t-curves-none.png"
r sr-t-curves-image-diff "$SR" --image "$A/t-curves-none.png" --compare "$A/t-curves-ref.png" --diff "$A/t-curves-d.png"
r sr-t-plain-camera "$SR" --size 64x48 --camera cam.json --cull back plain.json -o "$A/t-plain-p.png"
r sr-t-plain-below "$SR" --size 64x48 --perspective 55,1,0,1000 --lookat 0,-100,-5,0,0,-900 --cull back plain.json -o "$A/t-plain-q.png"
r sr-t-bgpattern "$SR" --size 4x3 --background-pattern c.pat --background 9,9,9 -o "$A/t-bg.png" emptyscene.json
r sr-t-bgpattern-big "$SR" --size 100x60 --background-pattern c.pat --background '#ff8800' -o "$A/t-bg-big.png" emptyscene.json
for aa in exact none ss4; do r sr-t-screen-$aa "$SR" --size 4x3 --aa $aa screen.json -o "$A/t-screen-$aa.png"; done
r sr-t-missing-pattern "$SR" --size 8x8 missingpat.json -o "$A/t-x.png"
r sr-t-iris "$SR" --size 256x192 --camera cam.json pyramid.json -o "$A/t-iris.png"
r sr-t-textbook "$SR" --size 256x192 --camera textbook.json pyramid.json -o "$A/t-textbook.png"
r sr-t-objects "$SR" --size 8x4 objects.json -o "$A/t-objects.png"
r sr-t-copies "$SR" --size 8x4 copies.json -o "$A/t-copies.png"
for b in ghost cycle singular; do r sr-t-$b "$SR" --size 8x4 $b.json -o "$A/t-bad.png"; done
r sr-t-fan-ref "$SR" --ortho2 0,512,0,384 --size 512x384 fan120.json --reference -o "$A/t-fan-ref.png"
r sr-t-fan-exact-compare "$SR" --ortho2 0,512,0,384 --size 512x384 fan120.json --compare "$A/t-fan-ref.png" --json -o "$A/t-fan-exact.png"
for t in 1 3; do
    for aa in exact ss4 none; do r sr-t-tris-$aa-t$t "$SR" --size 100x70 --aa $aa --threads $t tris200.json; done
done
rp sr-t-closed-pipe "{ $SR --size 2000x2000 --aa none --format ppm half.json; echo \"status=\$?\" >&2; } | head -c 100 > /dev/null"

echo "run.sh: scene-render frames and animation" >&2
FR=$O/frames; mkdir -p "$FR"
SPIN=(--perspective 55,1,0,1000 --lookat 0,100,-5,0,0,-900 --cull back --size 256x192)
r fr-spin-all "$SR" "${SPIN[@]}" --frames 36 "$O/make/demo2-spin.ndjson" -o "$FR/frame-%04d.png"
for k in 0 1 9 35; do
    r fr-spin-single-$k "$SR" "${SPIN[@]}" --frames 36 --frame $k "$O/make/demo2-spin.ndjson" -o "$FR/single-%d.png"
done
r fr-spin-plain-name "$SR" "${SPIN[@]}" --frames 36 --frame 3 "$O/make/demo2-spin.ndjson" -o "$FR/plain-name.png"
r fr-spin-four "$SR" "${SPIN[@]}" --frames 4 "$O/make/demo2-spin.ndjson" -o "$FR/all-%04d.png"
r fr-spin-threads "$SR" "${SPIN[@]}" --threads 2 --frames 36 --frame 5 "$O/make/demo2-spin.ndjson" -o "$FR/slurm-%04d.png"
r fr-spin-unpartitioned "$SR" "${SPIN[@]}" --frames 36 --frame 4 "$ROOT/fixtures/scenes/demo2-spin.json" -o "$FR/direct-%d.png"
r fr-err-no-pattern "$SR" --frames 3 -o "$FR/x.png" "$O/make/demo2-spin.ndjson"
r fr-err-no-output "$SR" --frames 3 "$O/make/demo2-spin.ndjson"
r fr-err-frame-range "$SR" --frames 3 --frame 3 -o "$FR/f%d.png" "$O/make/demo2-spin.ndjson"
r fr-err-frames0 "$SR" --frames 0 -o "$FR/f%d.png" "$O/make/demo2-spin.ndjson"
r fr-err-shrink "$SR" --frames 3 shrink.json -o "$FR/s%d.png" --size 4x4
TA=(--ortho -80,80,-60,60,0,100 --size 160x120 --frames 3)
r fr-turn-animate "$SR" "${TA[@]}" --animate --fps 4 -o "$FR/turn.png" "$ROOT/fixtures/scenes/two-spheres-turn.json"
r fr-turn-apng "$SR" "${TA[@]}" --animate -o "$FR/turn.apng" "$ROOT/fixtures/scenes/two-spheres-turn.json"
r fr-turn-frames "$SR" "${TA[@]}" -o "$FR/f-%d.png" "$ROOT/fixtures/scenes/two-spheres-turn.json"
r fr-turn-frames-ppm "$SR" "${TA[@]}" -o "$FR/f-%d.ppm" "$ROOT/fixtures/scenes/two-spheres-turn.json"
r fr-err-animate-pattern "$SR" "${TA[@]}" --animate -o "$FR/f-%d.png" "$ROOT/fixtures/scenes/two-spheres-turn.json"
r fr-err-animate-ppm "$SR" "${TA[@]}" --animate -o "$FR/t.ppm" "$ROOT/fixtures/scenes/two-spheres-turn.json"
r fr-err-quadric-tol0 "$SR" "${TA[@]}" --quadric-tolerance 0 -o "$FR/f-%d.png" "$ROOT/fixtures/scenes/two-spheres-turn.json"
r fr-err-fps0 "$SR" "${TA[@]}" --animate --fps 0 -o "$FR/t0.png" "$ROOT/fixtures/scenes/two-spheres-turn.json"
r fr-turn-single "$SR" --ortho -80,80,-60,60,0,100 --size 160x120 --frames 36 --frame 20 -o "$FR/turn20.png" "$ROOT/fixtures/scenes/two-spheres-turn.json"

echo "run.sh: scene-render textures, filters, boundaries, composition, quadrics, stripes, stress" >&2
X=$O/tex; mkdir -p "$X"
CAMT=(--perspective 60,1.333,0.1,100 --lookat 0,0.5,1,0,-0.5,-5 --size 96x72)
r tx-direct "$SR" "${CAMT[@]}" tex.json -o "$X/direct.png"
r tx-ref "$SR" "${CAMT[@]}" --reference tex.json -o "$X/ref.png"
r tx-p3 "$SR" "${CAMT[@]}" "$Q/t-tex.ndjson" -o "$X/p3.png"
r tx-p3-ref "$SR" "${CAMT[@]}" --reference "$Q/t-tex.ndjson" -o "$X/p3ref.png"
r tx-uv "$SR" "${CAMT[@]}" "$Q/t-texuv.ndjson" -o "$X/uv.png"
r tx-texuv-direct "$SR" "${CAMT[@]}" texuv.json -o "$X/texuv-direct.png"
for aa in exact none ss4; do r tx-aligned-$aa "$SR" --size 48x40 --aa $aa aligned.json -o "$X/aligned-$aa.ppm"; done
r tx-aligned-p3 "$SR" --size 48x40 "$Q/t-aligned.ndjson" -o "$X/aligned-p3.ppm"
r tx-quad2 "$SR" --size 400x300 quad2.json -o "$X/quad2.ppm"
r tx-quad20 "$SR" --size 400x300 quad20.json -o "$X/quad20.ppm"
for mode in repeat mirror edge clamp transparent; do
    r tx-xgl-$mode "$SR" --size 64x64 --boundary-color 9,8,7 --boundary $mode xgl.json -o "$X/xgl-$mode.ppm"
    r tx-xgl-bilinear-$mode "$SR" --size 64x64 --boundary-color 9,8,7 --filter bilinear --boundary $mode xgl.json -o "$X/xglb-$mode.ppm"
    r tx-xgl-trilinear-$mode "$SR" --size 32x32 --boundary-color 9,8,7 --filter trilinear --boundary $mode xgl.json -o "$X/xglt-$mode.ppm"
done
r tx-xgl-uv-precedence "$SR" --size 64x64 --boundary-color 9,8,7 --boundary-u repeat --boundary-v clamp xgl.json -o "$X/xgl-prec.ppm"
r tx-xgl-uv-precedence2 "$SR" --size 64x64 --boundary-u mirror --boundary-v edge xgl.json -o "$X/xgl-prec2.ppm"
r tx-xgl-uv-precedence3 "$SR" --size 64x64 --boundary transparent --boundary-u edge xgl.json -o "$X/xgl-prec3.ppm"
for np in "" --no-perspective-correction; do
    r tx-persp${np:+-none} "$SR" --size 100x100 --perspective 90,1,0.1,10 --aa none $np persp-uv.json -o "$X/persp${np:+-none}.ppm"
    r tx-persp-exact${np:+-none} "$SR" --size 100x100 --perspective 90,1,0.1,10 $np persp-uv.json -o "$X/perspx${np:+-none}.ppm"
done
r tx-compose-replace "$SR" --size 64x64 --background 0,255,0 compose.json -o "$X/c-replace.ppm"
r tx-compose-modulate "$SR" --size 64x64 --background 0,255,0 --compose modulate compose.json -o "$X/c-modulate.ppm"
r tx-compose-blend "$SR" --size 64x64 --background 0,255,0 --compose blend --compose-color1 255,0,0 --compose-color2 0,0,255 compose.json -o "$X/c-blend.ppm"
r tx-compose-blend-intrinsic "$SR" --size 64x64 --background 0,255,0 --compose blend-intrinsic --compose-color1 0,0,255 compose.json -o "$X/c-bi.ppm"
r tx-compose-decal "$SR" --size 64x64 --background 0,255,0 --compose decal --compose-color1 9,9,9 compose.json -o "$X/c-decal.ppm"
r tx-compose-decal-intrinsic "$SR" --size 64x64 --background 0,255,0 --compose decal-intrinsic compose.json -o "$X/c-di.ppm"
r tx-compose-modulate-trilinear "$SR" --size 32x32 --background 0,255,0 --compose modulate --filter trilinear compose.json -o "$X/c-mod-tri.ppm"
r tx-compose-decal-ss4 "$SR" --size 64x64 --aa ss4 --compose decal --compose-color1 9,9,9 compose.json -o "$X/c-decal-ss4.ppm"
r tx-compose-decal-noalpha "$SR" --size 40x30 --compose decal quad2.json -o "$X/c-err.png"
r tx-uvrecs-render "$SR" --size 96x72 "${CAMT[@]:0:4}" uvrecs.json -o "$X/uvrecs.png"
r tx-sliver-ref "$SR" --size 640x480 --perspective 60,1.333,0.1,100 --lookat 0,1.2,0,0,0,-12 sliver.json --reference -o "$X/sliver-ref.png"
r tx-sliver-exact "$SR" --size 640x480 --perspective 60,1.333,0.1,100 --lookat 0,1.2,0,0,0,-12 sliver.json -o "$X/sliver-exact.png"
for filter in box point bilinear mip-point mip-bilinear mip-point-linear trilinear ewa; do
    for aa in exact ss4 none; do
        r tx-filter-$filter-$aa "$SR" "${CAMT[@]}" --filter $filter --aa $aa tex.json -o "$X/f-$filter-$aa.ppm"
    done
done
r tx-filter-quad2-bilinear "$SR" --size 400x300 --filter bilinear quad2.json -o "$X/quad2-bilinear.ppm"
for filter in box point; do
    r tx-clamp-edge-$filter "$SR" --size 400x300 --boundary edge --filter $filter clampk.json -o "$X/clampk-$filter.ppm"
    r tx-line-$filter "$SR" --size 800x600 --filter $filter line.json -o "$X/line-$filter.ppm"
done
for mf in mip-point trilinear ewa; do r tx-err-magfilter-$mf "$SR" --mag-filter $mf quad2.json -o "$X/err.png"; done
for bias in nan inf -17 1e300; do r tx-err-lodbias-$bias "$SR" --lod-bias $bias quad2.json -o "$X/err.png"; done
r tx-lodbias-neg "$SR" --lod-bias -1.5 --filter trilinear --size 100x75 quad20.json -o "$X/lodbias-neg.png"
r tx-err-filter-cubic "$SR" --filter cubic quad2.json -o "$X/err.png"
r tx-err-minfilter-linear "$SR" --min-filter linear quad2.json -o "$X/err.png"
r tx-err-mipbuild-gauss "$SR" --mip-build gauss quad2.json -o "$X/err.png"
r tx-ref-ignores-filters "$SR" "${CAMT[@]}" --reference --filter ewa --lod-bias 2 --mip-build box tex.json -o "$X/ref-filters.ppm"
r tx-minfilter-trilinear "$SR" "${CAMT[@]}" --aa none --min-filter trilinear tex.json -o "$X/min-tri.ppm"
r tx-minfilter-ewa-magbox "$SR" "${CAMT[@]}" --min-filter ewa --mag-filter box tex.json -o "$X/min-ewa.ppm"
r tx-magfilter-bilinear "$SR" "${CAMT[@]}" --mag-filter bilinear --min-filter mip-bilinear tex.json -o "$X/mag-bil.ppm"
for run in repeat:mitchell:trilinear repeat:box:ewa repeat:box:mip-point-linear mirror:mitchell:trilinear \
           edge:mitchell:trilinear clamp:box:trilinear transparent:mitchell:ewa repeat:mitchell:mip-bilinear; do
    IFS=: read -r bnd build filter <<<"$run"
    r tx-c48-$bnd-$build-$filter "$SR" --size 64x48 --perspective 60,1.333,0.5,1000 --lookat 0,0,0,0,-0.05,-1 \
        --filter $filter --boundary $bnd --mip-build $build c48.json -o "$X/c48-$bnd-$build-$filter.ppm"
done
r tx-c48-lodbias "$SR" --size 64x48 --perspective 60,1.333,0.5,1000 --lookat 0,0,0,0,-0.05,-1 --filter trilinear --lod-bias 1 c48.json -o "$X/c48-bias.ppm"
SKF=(--size 96x64 --perspective 60,1.5,0.5,500 --lookat 0,1,0,0,0.6,-10 --threads 2)
i=0
for flags in "--aa exact" "--aa exact --filter trilinear" "--aa exact --min-filter ewa --mag-filter box" "--aa ss4 --filter trilinear"; do
    # shellcheck disable=SC2086
    r tx-skip-base$i "$SR" "${SKF[@]}" $flags skipscene.json -o "$X/skip-base$i.png"
    for skip in hidden mip transparent magnify hidden,mip,transparent,magnify; do
        # shellcheck disable=SC2086
        r tx-skip-no-$skip-$i "$SR" "${SKF[@]}" $flags --no-skip $skip skipscene.json -o "$X/skip-no-$skip-$i.png"
    done
    i=$((i + 1))
done
r tx-skip-err "$SR" --no-skip mip,blur emptyscene.json -o "$X/err.png"
# quadrics (quadric.rs)
QO=(--ortho 0,200,0,200,-100,100 --size 200x200)
for tol in 0.25 1; do r q-sphere-tol$tol "$SR" "${QO[@]}" --quadric-tolerance $tol sphere40.json -o "$X/sphere-$tol.png"; done
r q-sphere-hex "$SR" "${QO[@]}" sphere-hex.json -o "$X/sphere-hex.png"
r q-seam "$SR" "${QO[@]}" seam.json -o "$X/seam.png"
for i in 0 1 2 3 4 5 6 7 8 9 10 11; do r q-bad$i "$SR" qbad$i.json -o "$X/qbad.png"; done
r q-ball-direct "$SR" "${QO[@]}" --format ppm ball.json
r q-ball-expanded "$SR" "${QO[@]}" --format ppm cells-ball.ndjson
r q-direct "$SR" "${QO[@]}" --format ppm qdirect.json
r q-placed "$SR" "${QO[@]}" --format ppm qplaced.json
r q-golden-two-spheres "$SR" --ortho -80,80,-60,60,0,100 --size 800x600 --aa ss4 "$ROOT/fixtures/scenes/two-spheres.json" -o "$X/two-ss4.png"
r q-two-spheres-boundary "$SR" --ortho -80,80,-60,60,0,100 --size 400x300 --filter trilinear --boundary mirror "$ROOT/fixtures/scenes/two-spheres.json" -o "$X/two-tri.png"
r q-two-spheres-persp "$SR" --perspective 60,1.333,1,300 --lookat 0,0,60,0,0,-50 --size 400x300 "$ROOT/fixtures/scenes/two-spheres-turn.json" -o "$X/two-persp.png"
# stripes (stripe.rs)
for aa in none ss4 exact; do
    for lod in "--stripe-lod blended" "--stripe-lod nearest" "--cig-compat"; do
        l=${lod##* }
        # shellcheck disable=SC2086
        r st-flatwall-$aa-$l "$SR" --size 999x8 --aa $aa $lod flatwall.json -o "$X/flat-$aa-$l.png"
    done
done
r st-flatwall-ref "$SR" --size 999x8 --reference flatwall.json -o "$X/flat-ref.png"
SPV=(--size 160x120 --perspective 50,1.333,1,3000 --lookat 0,8,10,0,4,-100)
for extra in "" "--reference" "--aa none" "--aa ss4" "--cig-compat" "--stripe-lod nearest" "--cig-compat --aa none"; do
    n=$(echo "x $extra" | tr -d ' -'); n=${n#x}; n=${n:-default}
    for t in 1 3; do
        # shellcheck disable=SC2086
        r st-persp-$n-t$t "$SR" "${SPV[@]}" $extra --threads $t spersp.json -o "$X/spersp-$n-t$t.png"
    done
done
r st-err-cig-and-lod "$SR" --cig-compat --stripe-lod nearest spersp.json
r st-err-lod-trilinear "$SR" --stripe-lod trilinear spersp.json
for i in 0 1 2 3 4 5 6 7 8; do r st-err-record$i "$SR" --size 10x10 srbad$i.json -o "$X/st-out.png"; done
r st-err-both "$SR" --size 10x10 both.json -o "$X/st-out.png"
r st-instanced "$SR" --size 60x40 sinst.json -o "$X/sinst.png"
r st-flat "$SR" --size 60x40 sflat.json -o "$X/sflat.png"
r st-sscene "$SR" --size 160x120 --perspective 60,1.333,1,500 --lookat 0,20,30,0,0,-50 sscene.json -o "$X/sscene.png"
# stress (stress.rs)
r ss-t0 "$SR" --size 64x48 --perspective 60,1.3333,0.1,100 --lookat 0,0,0,0,0,-1 --format pam st-t0.json
r ss-t1e7 "$SR" --size 64x48 --perspective 60,1.3333,0.1,100 --lookat 1e7,1e7,1e7,1e7,1e7,9999999 --format pam st-t1e7.json
rp ss-t1e7-partitioned "$P3 st-t1e7.json | $SR --size 64x48 --perspective 60,1.3333,0.1,100 --lookat 1e7,1e7,1e7,1e7,1e7,9999999 --format pam -"
for e in -6 -3 3 6 9; do
    s=$(python3 -c "s=10.0**$e; print('%r,%r,%r,%r,%r,%r' % (-3*s,3*s,-2.25*s,2.25*s,0.0,20*s))")
    r ss-scale1e$e "$SR" --size 64x48 --ortho "$s" --format pam st-s1e$e.json
    rp ss-scale1e$e-partitioned "$P3 st-s1e$e.json | $SR --size 64x48 --ortho $s --format pam -"
done
for rep in 0 1000 10000000; do r ss-uv$rep "$SR" --size 64x48 --format pam st-uv$rep.json; done
for near in 0 0.01; do
    r ss-floor-near$near "$SR" --size 32x32 --perspective 60,1,$near,100 --format pam st-floor.json
    r ss-floorflat-near$near "$SR" --size 32x32 --perspective 60,1,$near,100 --format pam st-floorflat.json
    rp ss-floor-partitioned-near$near "$P3 st-floor.json | $SR --size 32x32 --perspective 60,1,$near,100 --format pam -"
done
for e in -6 -2 0 6; do r ss-incr1e$e "$SR" --size 16x16 --ortho2 0,1,0,1 --format pam st-incr1e$e.json; done
for i in 0 1; do r ss-fine$i "$SR" st-fine$i.json -o "$X/ss-out.pam"; done
for i in 0 1 2 3; do r ss-shift$i "$SR" --size 16x16 --ortho2 0,1,0,1 st-shift$i.json -o "$X/ss-shift$i.pam"; done
for size in 16 64 256 1024; do
    r ss-pattern$size-exact "$SR" --size 64x64 --aa exact --format pam st-p$size.json
    r ss-pattern$size-ss4 "$SR" --size 64x64 --aa ss4 --format pam st-p$size.json
done
for i in 0 1 2 3 4 5 6; do r ss-json$i "$SR" st-json$i.json -o "$X/ss-out.pam"; done
for i in 0 1 2 3; do r ss-huge$i "$SR" --size 16x16 --format pam st-huge$i.json; done
r ss-star20002 "$SR" --size 16x16 st-star20002.json -o "$X/ss-out.pam"
r ss-star2000 "$SR" --size 16x16 --format pam st-star2000.json
r ss-disc20000 "$SR" --size 16x16 --format pam st-disc20000.json
r ss-circle "$SR" --size 16x16 --format pam st-circle.json
# errors (scene_render.rs bad_inputs_fail_cleanly_leaving_nothing)
r sr-err-nan "$SR" nan.json -o "$X/err.png"
r sr-err-missing "$SR" missing.json -o "$X/err.png"
r sr-err-size-huge "$SR" --size 100000x100000 half.json -o "$X/err.png"
r sr-err-size-empty "$SR" --size 0x5 half.json -o "$X/err.png"
r sr-err-ss3 "$SR" --aa ss3 half.json -o "$X/err.png"
r sr-err-ss512 "$SR" --aa ss512 half.json -o "$X/err.png"
r sr-err-aa-bogus "$SR" --aa fast half.json -o "$X/err.png"
r sr-err-persp0 "$SR" --perspective 0,1,0,10 half.json -o "$X/err.png"
r sr-err-ortho2-empty "$SR" --ortho2 0,0,0,1 half.json -o "$X/err.png"
r sr-err-compare-missing "$SR" --compare nope.png half.json -o "$X/err.png"
r sr-err-diff-alone "$SR" --diff d.png half.json -o "$X/err.png"
r sr-err-json-alone "$SR" --json half.json -o "$X/err.png"
r sr-err-image-alone "$SR" --image "$A/t-half.png" -o "$X/err.png"
r sr-err-background "$SR" --background 300,0,0 half.json -o "$X/err.png"
r sr-err-background-hex "$SR" --background '#12345' half.json -o "$X/err.png"
r sr-err-maxerr-removed "$SR" --max-error 1 half.json -o "$X/err.png"
r sr-err-refsamples "$SR" --reference --reference-samples 7 half.json -o "$X/err.png"
r sr-err-threads0 "$SR" --threads 0 half.json -o "$X/err.png"
r sr-err-unknown-ext "$SR" half.json -o "$X/err.jpg"
r sr-err-bgpattern-missing "$SR" --background-pattern nope.pat half.json -o "$X/err.png"
r sr-err-compare-size "$SR" --image "$A/t-half.png" --compare "$A/t-curves-ref.png"
r sr-err-image-not-png "$SR" --image junk.png --compare "$A/t-half.png"
r sr-err-malformed "$SR" p3bad3.json -o "$X/err.png"
r sr-err-truncated "$SR" st-json6.json -o "$X/err.png"
rp sr-err-leftovers "ls -A '$X' | grep -c err || true"
CWD=$ROOT

###########################################################################
echo "run.sh: bench/ scenes" >&2
BO=$O/bench; mkdir -p "$BO"
# bench/texture.sh + bench/tradeoff.sh (bench/texbench.py): every method but llvmpipe
CWD=$S/texbench
TB=(
  "plane|plane.json|320x240|--perspective 60,1.333,0.5,1000 --lookat 0,2,0,0,1.2,-20"
  "wall|wall.json|640x480|--perspective 60,1.333,0.5,100 --lookat 0,0,0,0,0,-10"
  "demo2|$ROOT/examples/scenes/demo2.json|1024x768|--perspective 55,1,0,1000 --lookat 0,100,-5,0,0,-900 --cull back"
  "demo1|$ROOT/examples/scenes/demo1.json|1024x768|--ortho2 0,1023,0,767 --background 255,255,255"
  "tiles|tiles.json|640x480|--perspective 60,1.333,0.1,100 --lookat 0,1.2,0,0,0,-12"
)
for spec in "${TB[@]}"; do
    IFS='|' read -r name scene size cam <<<"$spec"
    # shellcheck disable=SC2086
    {
    r tb-$name-reference "$SR" --size $size $cam --reference --json "$scene" -o "$BO/tb-$name-ref.png"
    imgs=()
    for m in "exact|--aa exact" "ss16|--aa ss16" "ss4|--aa ss4" "none|--aa none" \
             "point|--aa exact --filter point" "bilinear|--aa exact --filter bilinear" "mip-point|--aa exact --filter mip-point" \
             "mip-bilinear|--aa exact --filter mip-bilinear" "mip-point-linear|--aa exact --filter mip-point-linear" \
             "trilinear|--aa exact --filter trilinear" "ewa|--aa exact --filter ewa"; do
        IFS='|' read -r mn margs <<<"$m"
        rt tb-$name-$mn "$SR" --size $size $cam $margs --timings "$scene" -o "$BO/tb-$name-$mn.png"
        imgs+=("$mn")
    done
    if [ "$name" != demo1 ]; then   # demo1 has no object-mode pattern: scaled() returns False, the bench skips it
        for factor in 4.0 2.0 1.0 0.5; do
            if [ "$name" = plane ] && [ "$factor" = 0.5 ]; then continue; fi  # 640,000 polygons: left out (time, size)
            rpt tb-$name-p3x$factor "$P3 $name-x$factor.json | $SR --size $size $cam --aa exact --timings - -o '$BO/tb-$name-p3x$factor.png'"
            imgs+=("p3x$factor")
        done
    fi
    r tb-$name-uv "$P3" --uv "$scene" -o "$BO/tb-$name-uv.json"
    r tb-$name-uv-render "$SR" --size $size $cam "$BO/tb-$name-uv.json" -o "$BO/tb-$name-uvr.png"
    imgs+=("uvr")
    for mn in "${imgs[@]}"; do
        r tb-$name-$mn-compare "$SR" --image "$BO/tb-$name-$mn.png" --compare "$BO/tb-$name-ref.png" --json
    done
    }
done
r tb-help-filters "$SR" --help
# bench/skips.sh (bench/skips.py): each skip with and without --no-skip, one thread
CWD=$S/skips
WIDE="--perspective 60,1.333,0.5,1000 --lookat 0,2,0,0,1.2,-20"
HEAD="--perspective 60,1.333,0.5,100 --lookat 0,0,0,0,0,-10"
SKIPS=(
  "hidden-ewa|hidden|hidden.json|640x480|$WIDE --aa exact --filter ewa"
  "hidden-ss16|hidden|hidden.json|320x240|$WIDE --aa ss16 --filter trilinear"
  "hidden-box|hidden|hidden.json|640x480|$WIDE --aa exact"
  "mip|mip|mip.json|320x240|$HEAD --aa exact --filter trilinear"
  "transparent|transparent|transparent.json|640x480|$WIDE --aa exact"
  "magnify|magnify|magnify.json|640x480|$HEAD --aa exact"
)
for spec in "${SKIPS[@]}"; do
    IFS='|' read -r label skip scene size flags <<<"$spec"
    # shellcheck disable=SC2086
    rt sk-$label-with "$SR" --size $size --threads 1 --timings $flags $scene -o "$BO/sk-$label-with.png"
    # shellcheck disable=SC2086
    rt sk-$label-without "$SR" --size $size --threads 1 --timings $flags --no-skip $skip $scene -o "$BO/sk-$label-without.png"
done
rt sk-referenced-one "$SR" --size 640x320 --threads 1 --timings --ortho2 0,20,0,10 referenced/one.json -o "$BO/sk-referenced-one.png"
rt sk-referenced-all "$SR" --size 640x320 --threads 1 --timings --ortho2 0,20,0,10 referenced/all.json -o "$BO/sk-referenced-all.png"
# bench/stripe.sh: every row x --aa, the reference, errors of the stripe rows
CWD=$S/stripe
SV=(--size 1024x768 --perspective 50,1.333,1,3000 --lookat 0,8,10,0,4,-100)
rt stb-reference "$SR" "${SV[@]}" --threads 1 --timings --reference stripe.json -o "$BO/stb-ref.png"
for row in "nearest|stripe.json|--stripe-lod nearest" "blended|stripe.json|--stripe-lod blended" "cig|stripe.json|--cig-compat" \
           "pattern|pattern.json|" "pattern-trilinear|pattern.json|--filter trilinear"; do
    IFS='|' read -r label scene flags <<<"$row"
    for aa in exact none ss4; do
        # shellcheck disable=SC2086
        rt stb-$label-$aa "$SR" "${SV[@]}" --threads 1 --timings $flags --aa $aa $scene -o "$BO/stb-$label-$aa.png"
        if [ "$scene" = stripe.json ]; then
            r stb-$label-$aa-compare "$SR" --image "$BO/stb-$label-$aa.png" --compare "$BO/stb-ref.png" --json
        fi
    done
done
r stb-ppm-devnull-format "$SR" "${SV[@]}" --threads 1 --stripe-lod nearest --aa none stripe.json -o "$BO/stb-nearest-none.ppm" --format ppm
# The former bench/max_error.sh's five scenes: --reference and --aa exact, the error achieved
CWD=$S/maxerr
r me-demo2-incr2.ndjson "$P3" demo2.json -o demo2-incr2.ndjson
ME=(
  "demo1|$ROOT/examples/scenes/demo1.json|--ortho2 0,1023,0,767 --background 255,255,255"
  "demo2-incr2|demo2-incr2.ndjson|${D2[*]} --background-pattern $BK"
  "demo2-direct|demo2.json|${D2[*]} --background-pattern $BK"
  "plane|plane.json|--perspective 60,1.333,0.5,1000 --lookat 0,2,0,0,1.2,-20"
  "fan|fan.json|--ortho2 0,1024,0,768"
)
for spec in "${ME[@]}"; do
    IFS='|' read -r name scene flags <<<"$spec"
    size=1024x768
    [ "$name" = fan ] && size=512x384   # REDUCED: the fan's reference takes 25 s at 1024x768 (same view, half the pixels)
    # shellcheck disable=SC2086
    {
    r me-$name-reference "$SR" $scene $flags --size $size --reference -o "$BO/me-$name-ref.png"
    r me-$name-exact "$SR" $scene $flags --size $size --aa exact -o "$BO/me-$name-exact.png"
    r me-$name-exact-compare "$SR" --image "$BO/me-$name-exact.png" --compare "$BO/me-$name-ref.png" --json
    }
done
# bench/scene_render.sh (+ scene_render_bench.py): demo2 at incr 2 and 1 through polyfill3 and
# through the stand-in bench/demo2_scene.py, with and without culling; random triangles (REDUCED)
CWD=$S/scenerender
for incr in 2 1; do
    r srb-demo2-incr$incr.ndjson "$P3" demo2-incr$incr.json -o "$BO/srb-demo2-incr$incr.ndjson"
done
SRB=(
  "demo2-incr2|$BO/srb-demo2-incr2.ndjson|"
  "demo2-incr1|$BO/srb-demo2-incr1.ndjson|"
  "demo2-incr2-cull|$BO/srb-demo2-incr2.ndjson|--cull back"
  "demo2-incr1-cull|$BO/srb-demo2-incr1.ndjson|--cull back"
  "demo2py-incr2|demo2-py-incr2.ndjson|"
  "demo2py-incr1-cull|demo2-py-incr1.ndjson|--cull back"
)
for spec in "${SRB[@]}"; do
    IFS='|' read -r name scene cull <<<"$spec"
    base="--size 1024x768 --background 20,20,80 --perspective 55.0,1.0,0.0,1000.0 --lookat 0.0,100.0,-5.0,0.0,0.0,-900.0 $cull"
    # shellcheck disable=SC2086
    {
    r srb-$name-reference "$SR" $base --reference --json "$scene" -o "$BO/srb-$name-ref.png"
    for aa in none ss4 ss16 exact; do
        rt srb-$name-$aa "$SR" $base --aa $aa --timings "$scene" -o "$BO/srb-$name-$aa.png"
        r srb-$name-$aa-compare "$SR" --image "$BO/srb-$name-$aa.png" --compare "$BO/srb-$name-ref.png" --json
    done
    }
done
for aa in none ss4 ss16 exact; do
    rt srb-triangles100k-$aa "$SR" --size 1024x768 --background 20,20,80 --aa $aa --timings triangles-100k.ndjson -o "$BO/srb-tris-$aa.png"
done
r srb-triangles100k-threads1 "$SR" --size 1024x768 --background 20,20,80 --threads 1 triangles-100k.ndjson -o "$BO/srb-tris-t1.png"
# bench/animate.sh: the turning pyramid at incr 2 and 1, 1024x768, --aa exact; per frame and one process
CWD=$S/animate
CAMA=(--perspective 55,1,0,1000 --lookat 0,100,-5,0,0,-900 --cull back --size 1024x768 --aa exact)
for incr in 2 1; do
    r an-spin-incr$incr.ndjson "$P3" -o "$BO/an-spin-incr$incr.ndjson" spin-incr$incr.json
    for k in 0 17 35; do
        r an-incr$incr-pf-$k "$SR" "${CAMA[@]}" --frames 36 --frame $k -o "$BO/an-incr$incr-pf-%04d.png" "$BO/an-spin-incr$incr.ndjson"
    done
    rpt an-four-incr$incr-json "$P3 --json four-incr$incr.json > /dev/null"
    rpt an-fig51-incr$incr-json "$P3 --json fig51-incr$incr.json > /dev/null"
done
r an-incr2-seq "$SR" "${CAMA[@]}" --frames 36 -o "$BO/an-incr2-seq-%04d.png" "$BO/an-spin-incr2.ndjson"
r an-incr1-seq-reduced "$SR" "${CAMA[@]:0:6}" --size 512x384 --aa exact --frames 36 -o "$BO/an-incr1-seq-%04d.png" "$BO/an-spin-incr1.ndjson"
CWD=$ROOT

###########################################################################
# Absolute paths of this run must not leak into what is compared.
if [ ${#OUT} -ge ${#BIN} ]; then first=$OUT second=$BIN; m1=@OUT@ m2=@BIN@; else first=$BIN second=$OUT; m1=@BIN@ m2=@OUT@; fi
grep -rlF -- "$first" "$OUT" 2>/dev/null | while IFS= read -r f; do sed -i "s#$first#$m1#g" "$f"; done
grep -rlF -- "$second" "$OUT" 2>/dev/null | while IFS= read -r f; do sed -i "s#$second#$m2#g" "$f"; done
END=$(date +%s)
nonzero=$(grep -Lx 0 "$LOG"/*.rc | wc -l)
{
    echo "invocations: $N"
    echo "nonzero exit: $nonzero"
    echo "duplicate names: $DUP"
    echo "seconds: $((END - START))"
    echo "files: $(find "$OUT" -type f | wc -l)"
} | tee "$OUT/summary.nocmp" >&2
