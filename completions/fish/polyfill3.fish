complete -c polyfill3 -s o -l output -d 'Output file (NDJSON), `-` for standard output' -r
complete -c polyfill3 -l pattern -d 'Pattern, in "object" mode, for every polygon record without a "pattern" or "stripe" of its own, and the file of those whose "pattern" names none (relative to the current directory)' -r -F
complete -c polyfill3 -l incr -d 'Side of one texel in world units, for records without "incr"' -r
complete -c polyfill3 -l rotate -d 'Degrees counter-clockwise of the pattern\'s x from the first edge, for records without "rotate"' -r
complete -c polyfill3 -l horz -d 'Shift of the pattern right in texels, for records without "horz"' -r
complete -c polyfill3 -l vert -d 'Shift of the pattern up in texels, for records without "vert"' -r
complete -c polyfill3 -l merge -d 'Join same-coloured whole cells into one polygon (the record gets "cells": how many): runs along a row (HOW rows, the default), or rectangles of them, runs of consecutive rows over the same columns (HOW blocks: fewer vertices, the same region). Every grid corner on the polygon\'s sides is kept, so neighbours meet it vertex to vertex' -r -f -a "rows\t'Runs of cells along a row'
blocks\t'Rectangles of cells: runs of consecutive rows over the same columns joined'"
complete -c polyfill3 -l compat -d 'Reproduce another algorithm: `thesis` is the thesis\'s loop, degenerate polygons included (horz and vert must be integers)' -r -f -a "thesis\t'The thesis\'s loop (Fig. 4.7): accumulated grid, inclusive bounds, degenerate polygons along the far edges'"
complete -c polyfill3 -l planarity-tol -d 'Largest distance of a vertex from the polygon\'s plane, relative to the polygon\'s size (bounding-box diagonal)' -r
complete -c polyfill3 -l max-polygons -d 'Refuse a job that would make more polygons than this: texel cells (estimated from each polygon\'s area / incr² before its cells are written) and quadric triangles. Records passed through unchanged are the input\'s own and not counted' -r
complete -c polyfill3 -l tolerance -d 'Largest distance of a circle\'s or arc\'s chords from the true curve, in world units (for "circle" and "arc" records); also sets the slices and stacks a quadric record leaves out' -r
complete -c polyfill3 -l camera -d 'Camera JSON file (`-` = standard input); excludes every other camera flag. Default: none (the tool\'s default view)' -r
complete -c polyfill3 -l lookat -d 'IRIS/GLU lookat: eye and center points. Default: none (identity view, eye at the origin looking down -z)' -r
complete -c polyfill3 -l up -d 'Up direction for --lookat. Default: 0,1,0' -r
complete -c polyfill3 -l twist -d 'IRIS lookat twist in degrees (right-hand rotation of the camera about its line of sight). Default: 0' -r
complete -c polyfill3 -l perspective -d 'gluPerspective: vertical field of view in degrees, aspect (width/height, or `auto` for the image\'s own), near and far distances (near may be 0). Default: none' -r
complete -c polyfill3 -l ortho -d 'glOrtho: left, right, bottom, top, near, far in eye coordinates. Default: none' -r
complete -c polyfill3 -l ortho2 -d 'IRIS ortho2 (gluOrtho2D): left, right, bottom, top; near -1, far 1. Default: none' -r
complete -c polyfill3 -l vrp -d 'Textbook view reference point (world). Default: 0,0,0' -r
complete -c polyfill3 -l vpn -d 'View plane normal: the direction the camera looks. Default: 0,0,-1 (-1,-1,-1 with --oblique isometric)' -r
complete -c polyfill3 -l view-up -d 'View-up direction (world), shown vertical on the image. Default: 0,1,0' -r
complete -c polyfill3 -l view-distance -d 'Distance from the VRP to the view plane along the VPN. Default: 0' -r
complete -c polyfill3 -l window -d 'Window on the view plane (view plane coordinates, centred on the VPN line through the VRP); it fills the image. Default: none (required)' -r
complete -c polyfill3 -l cop -d 'Perspective: centre of projection (world coordinates, on the viewer\'s side of the view plane). Default: none' -r
complete -c polyfill3 -l dop -d 'Parallel: direction of projection (world; oblique when not along the VPN). Default: none' -r
complete -c polyfill3 -l oblique -d 'Parallel: cavalier or cabinet oblique projection with the receding axis at ANGLE degrees (default 45), or isometric (no angle). Default: none' -r
complete -c polyfill3 -l front -d 'Front clipping plane: distance from the VRP along the VPN. Default: none (required)' -r
complete -c polyfill3 -l back -d 'Back clipping plane: distance from the VRP along the VPN. Default: none (required)' -r
complete -c polyfill3 -l cull -d 'Drop cells wholly outside the camera\'s view volume, and whole polygons turning it the FACES side (back, front, or none: keep both), before they are written: what `scene-render --cull FACES` with the same camera would not draw. --cull alone is --cull=back; the words back, front and none after it are its value (a file so named is ./none). Needs a camera' -r -f -a "none\t'Draw both faces'
back\t'Drop polygons seen from behind (clockwise on screen)'
front\t'Drop polygons seen from the front (counter-clockwise on screen)'"
complete -c polyfill3 -l depfile -d 'Write the make rule of the output: every file the run read (the input, the patterns, --camera, --pattern), as `cc -MD` does. Needs -o' -r
complete -c polyfill3 -l threads -d 'Worker threads (default: all cores). The output is identical for any N' -r
complete -c polyfill3 -l uv -d 'Do not partition: write each "object"-mode polygon whole (curves flattened) with its placement as per-vertex "uv" texel coordinates and "pattern": {"file": ABSOLUTE PATH, "mode": "uv"}, for renderers that take texture coordinates. --cull drops whole polygons'
complete -c polyfill3 -l json -d 'Print a JSON summary to standard error: {"version": 1, "tool": "polyfill3", ...} (docs/json.md)'
complete -c polyfill3 -l no-progress -d 'Show no progress bar. Bars are drawn on standard error only when it is a terminal (and TERM is not "dumb"), never into a pipe or a file, and cleared when the job ends'
complete -c polyfill3 -s h -l help -d 'Print help (see more with \'--help\')'
complete -c polyfill3 -s V -l version -d 'Print version'
