complete -c polyfill3 -s o -l output -d 'Output file (NDJSON), `-` for standard output' -r
complete -c polyfill3 -l pattern -d 'Pattern, in "object" mode, for every polygon record without a "pattern" or "stripe" of its own, and the file of those whose "pattern" names none (relative to the current directory)' -r -F
complete -c polyfill3 -l incr -d 'Side of one texel in world units, for records without "incr"' -r
complete -c polyfill3 -l rotate -d 'Degrees counter-clockwise of the pattern\'s x from the first edge, for records without "rotate"' -r
complete -c polyfill3 -l horz -d 'Shift of the pattern right in texels, for records without "horz"' -r
complete -c polyfill3 -l vert -d 'Shift of the pattern up in texels, for records without "vert"' -r
complete -c polyfill3 -l compat -d 'Reproduce another algorithm: `thesis` is the thesis\'s loop, degenerate polygons included (horz and vert must be integers)' -r -f -a "thesis\t'The thesis\'s loop (Fig. 4.7): accumulated grid, inclusive bounds, degenerate polygons along the far edges'"
complete -c polyfill3 -l planarity-tol -d 'Largest distance of a vertex from the polygon\'s plane, relative to the polygon\'s size (bounding-box diagonal)' -r
complete -c polyfill3 -l max-polygons -d 'Refuse a job that would write more polygons than this (estimated from each polygon\'s area / incr² before its cells are written)' -r
complete -c polyfill3 -l tolerance -d 'Largest distance of a circle\'s or arc\'s chords from the true curve, in world units (for "circle" and "arc" records)' -r
complete -c polyfill3 -l camera -d 'Camera JSON file (patkit-camera(5)) for --cull' -r
complete -c polyfill3 -l depfile -d 'Write the make rule of the output: every file the run read (the input, the patterns, --camera, --pattern), as `cc -MD` does. Needs -o' -r
complete -c polyfill3 -l merge -d 'Join runs of same-coloured whole cells of a row into one polygon (the record gets "cells": how many)'
complete -c polyfill3 -l cull -d 'Drop polygons facing away from the --camera and cells wholly outside its view volume before they are written'
complete -c polyfill3 -l uv -d 'Do not partition: write each "object"-mode polygon whole (curves flattened) with its placement as per-vertex "uv" texel coordinates and "pattern": {"file": ABSOLUTE PATH, "mode": "uv"}, for renderers that take texture coordinates. --cull drops whole polygons'
complete -c polyfill3 -l json -d 'Print a JSON summary to standard error: {"version": 1, "tool": "polyfill3", ...} (docs/json.md)'
complete -c polyfill3 -l no-progress -d 'Show no progress bar. Bars are drawn on standard error only when it is a terminal (and TERM is not "dumb"), never into a pipe or a file, and cleared when the job ends'
complete -c polyfill3 -s h -l help -d 'Print help (see more with \'--help\')'
complete -c polyfill3 -s V -l version -d 'Print version'
