#!/usr/bin/env bash
# Runs every Taut test from a clean clone on a fresh Debian machine with Rust.
# Installs what the tests need when it is missing, then runs the whole workspace's tests.
set -euo pipefail
cd "$(dirname "$0")/.."

need=()
# The tests build gltf's image support and the app's dependencies with the system C compiler.
command -v cc >/dev/null 2>&1 || need+=(gcc)
command -v pkg-config >/dev/null 2>&1 || need+=(pkg-config)
# The render tests draw on Mesa's software Vulkan driver (lavapipe) through the Vulkan loader.
installed() { dpkg-query -W -f='${Status}' "$1" 2>/dev/null | grep -q "install ok installed"; }
installed mesa-vulkan-drivers || need+=(mesa-vulkan-drivers)
installed libvulkan1 || need+=(libvulkan1)
# The editor's real-window test: a virtual X server, synthetic input and screen grabs.
command -v Xvfb >/dev/null 2>&1 || need+=(xvfb)
command -v xdotool >/dev/null 2>&1 || need+=(xdotool)
command -v import >/dev/null 2>&1 || need+=(imagemagick)
# The STEP export tests read Taut's files back with an independent CAD kernel, OpenCascade, through
# PyPI's cadquery-ocp-novtk, and the cage test compares with MeshLab through PyPI's pymeshlab, both in
# a virtual environment of their own (.venv-cad). Making that environment needs python3 and its venv
# module; Debian ships ensurepip, which venv needs, apart in python3-venv. pymeshlab's wheel links to
# the system's OpenGL, fontconfig and X11 client libraries even when it draws nothing.
cad_ready() { .venv-cad/bin/python -c 'import OCP, pymeshlab' >/dev/null 2>&1; }
if ! cad_ready; then
    command -v python3 >/dev/null 2>&1 || need+=(python3)
    python3 -c 'import venv, ensurepip' >/dev/null 2>&1 || need+=(python3-venv)
    for package in libgl1 libopengl0 libfontconfig1; do
        installed "$package" || need+=("$package")
    done
fi
if [ ${#need[@]} -gt 0 ]; then
    echo "installing: ${need[*]}"
    SUDO=""
    [ "$(id -u)" -ne 0 ] && SUDO="sudo"
    $SUDO apt-get update -qq
    DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq "${need[@]}"
fi

# A missing or broken .venv-cad (no OCP or pymeshlab, or its python gone) is made anew; the versions
# are pinned so that every machine measures with the same kernels.
if ! cad_ready; then
    echo "installing: cadquery-ocp-novtk and pymeshlab into .venv-cad"
    python3 -m venv --clear .venv-cad
    .venv-cad/bin/pip install --quiet cadquery-ocp-novtk==8.0.1.1.0 pymeshlab==2025.7.post1
fi
export TAUT_CAD_PYTHON="$PWD/.venv-cad/bin/python"

# Software rendering needs a runtime directory; a CI shell may not have one.
if [ -z "${XDG_RUNTIME_DIR:-}" ]; then
    export XDG_RUNTIME_DIR="$(mktemp -d)"
fi

# A one-shot build gains nothing from incremental caches, which take gigabytes of disk; set
# CARGO_INCREMENTAL=1 to keep them between runs. The free space is printed to explain a full disk.
export CARGO_INCREMENTAL="${CARGO_INCREMENTAL:-0}"
echo "free disk for target/: $(df -h --output=avail . | tail -1 | tr -d ' ')"

# The real-window test drives the release binary, as a designer runs it.
cargo build --release --locked -p taut-app
export TAUT_EDITOR_BIN="$PWD/target/release/taut"

cargo test --workspace --locked "$@"
