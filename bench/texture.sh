#!/bin/sh
# Direct texturing in scene-render against its reference, the polyfill3 path
# and Mesa's llvmpipe (issue 7): per scene, render time, whole-process time
# and error of every --aa mode (and every --filter when scene-render has the
# flag), `polyfill3 | scene-render`, and llvmpipe at nearest, trilinear and
# 16x anisotropic trilinear with and without MSAA 4x; then the issue's goals
# computed from the numbers.
#
#   bench/texture.sh > bench/RESULTS-texture.md      # all five scenes
#   bench/texture.sh photo-plane photo-sphere        # only those
#
# Scenes: a checkered plane receding to the horizon (heavy minification), a
# close-up wall (magnification, crisp texel edges), and the thesis's demo 2
# (App. C) drawn directly; and a 1024x1024 photograph (an image texture, no
# .pat: issue 19) on the plane and wrapped around a sphere. Name scenes to
# run only those. The driver is bench/texbench.py; llvmpipe draws
# `polyfill3 --uv` streams with bench/llvmpipe_texture.py.
set -eu
cd "$(dirname "$0")/.."
BENCH=texture
. bench/setup.sh
. bench/venv.sh
"$VENV/bin/python" bench/texbench.py texture "$TARGET/release" "$WORK" "$@"
