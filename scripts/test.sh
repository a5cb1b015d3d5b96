#!/usr/bin/env bash
# Builds and runs the whole test suite with CTest (KITTI tests skip when ../shared is absent).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/build.sh "$@"
cd "${TIGRIS_BUILD_DIR:-build}"
ctest --output-on-failure -j"$(nproc)"
