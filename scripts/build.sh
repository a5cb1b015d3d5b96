#!/usr/bin/env bash
# Installs missing packages, then configures and builds everything into build/ (Release).
# Extra arguments go to the CMake configure step, e.g. -DTIGRIS_SANITIZE=ON.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/deps.sh
build_dir=${TIGRIS_BUILD_DIR:-build}
cmake -S . -B "$build_dir" -DCMAKE_BUILD_TYPE=Release "$@" >/dev/null
cmake --build "$build_dir" -j"$(nproc)"
