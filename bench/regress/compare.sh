#!/usr/bin/env bash
# Compares two regression corpora written by bench/regress/run.sh:
#
#   bash bench/regress/compare.sh DIR_A DIR_B
#
# Runs cmp on every file of either directory (files named *.nocmp, which hold
# timing figures, are skipped), lists each difference (or a file present on
# one side only), and ends with "N files identical, M differ". Exit status 1
# if any file differs, 0 otherwise, 2 on a usage error.
set -u
if [ $# -ne 2 ] || [ ! -d "$1" ] || [ ! -d "$2" ]; then
    echo "usage: bash $0 DIR_A DIR_B" >&2
    exit 2
fi
A=$1 B=$2
same=0 differ=0 skipped=0
while IFS= read -r -d '' f; do
    case "$f" in *.nocmp) skipped=$((skipped + 1)); continue ;; esac
    if [ ! -e "$A/$f" ]; then
        echo "only in $B: $f"; differ=$((differ + 1))
    elif [ ! -e "$B/$f" ]; then
        echo "only in $A: $f"; differ=$((differ + 1))
    elif msg=$(cmp -- "$A/$f" "$B/$f" 2>&1); then
        same=$((same + 1))
    else
        echo "differs: $f (${msg#"$A/$f" "$B/$f" })"; differ=$((differ + 1))
    fi
done < <( { (cd "$A" && find . -type f -printf '%P\0'); (cd "$B" && find . -type f -printf '%P\0'); } | sort -zu)
[ "$skipped" -gt 0 ] && echo "($skipped *.nocmp files with timing figures not compared)"
echo "$same files identical, $differ differ"
[ "$differ" -eq 0 ]
