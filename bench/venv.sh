# Sourced by the llvmpipe benchmarks (bench/scene_render.sh, bench/texture.sh,
# bench/tradeoff.sh): sets VENV to a Python venv under $TARGET with moderngl,
# numpy and matplotlib (pip from PyPI), and checks that Mesa's EGL/llvmpipe
# works (apt-get when root and missing).
VENV="$TARGET/bench-scene-render/venv"
if ! "$VENV/bin/python" -c 'import moderngl, numpy, matplotlib' 2>/dev/null; then
    python3 -m venv "$VENV" >&2
    "$VENV/bin/pip" install -q moderngl numpy matplotlib >&2
fi
if ! "$VENV/bin/python" -c 'import moderngl; moderngl.create_standalone_context(backend="egl")' 2>/dev/null; then
    if [ "$(id -u)" = 0 ] && command -v apt-get >/dev/null; then
        apt-get install -y -q libegl1 libgl1-mesa-dri >&2
    fi
    "$VENV/bin/python" -c 'import moderngl; moderngl.create_standalone_context(backend="egl")' >&2 || {
        echo "llvmpipe (EGL) is not available on this machine" >&2
        exit 1
    }
fi
