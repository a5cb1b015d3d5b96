#!/usr/bin/env bash
# Installs missing packages, then configures and builds everything into build/ (Release).
# Extra arguments go to the CMake configure step, e.g. -DTIGRIS_SANITIZE=ON.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/deps.sh
build_dir=${TIGRIS_BUILD_DIR:-build}
# An existing build folder is configured already (the build step re-runs CMake itself when a
# CMakeLists.txt changed), so only a new folder or new options pay for a configure.
if [ $# -gt 0 ] || [ ! -f "$build_dir/CMakeCache.txt" ]; then
  cmake -S . -B "$build_dir" -DCMAKE_BUILD_TYPE=Release "$@" >/dev/null
fi
cmake --build "$build_dir" -j"$(nproc)"
