#!/usr/bin/env bash
# Installs rigidae's dependencies from Debian 12's packages (only those
# missing) and builds everything (the rigidae CLI, the Python module and the
# test suite) in ./build.
set -euo pipefail
cd "$(dirname "$0")/.."

packages=(g++ cmake ninja-build pkg-config
          libsundials-dev libeigen3-dev libsuitesparse-dev libfmt-dev doctest-dev
          libtomlplusplus-dev nlohmann-json3-dev
          libtinyxml2-dev                        # URDF files (src/io/urdf_reader.cpp)
          libmujoco-dev libqhull-dev             # the URDF arm's MuJoCo cross-check (tests/mujoco/); qhull: named by mujoco::mujoco
          python3-numpy python3-matplotlib
          python3-dev pybind11-dev python3-pytest
          python3-venv python3-pip python3-setuptools python3-wheel  # pip install . (README "Install")
          chromium             # the viewer's test opens its page headless (tests/python/test_view.py)
          ffmpeg)              # rigidae animate --out X.mp4, and ffprobe in its test
# npm fetches three.js for rigidae view into build/ (CMakeLists.txt). Debian's
# npm package conflicts with a Node.js installed from elsewhere (NodeSource's
# nodejs ships its own npm): install it only when no npm is on PATH.
command -v npm >/dev/null || packages+=(npm)
bash tools/install_missing.sh rigidae "${packages[@]}"

# ccache, when present, shares compiled objects between checkouts of the
# same tree (CCACHE_BASEDIR makes its keys independent of the folder).
launcher=()
if command -v ccache >/dev/null; then
  export CCACHE_BASEDIR="$PWD"
  launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
fi
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release "${launcher[@]}" >/dev/null
cmake --build build -j"$(nproc)"
