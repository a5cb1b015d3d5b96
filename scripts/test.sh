#!/usr/bin/env bash
# Builds and runs the whole test suite with CTest (KITTI tests skip when ../shared is absent).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/build.sh "$@"
cd "${TIGRIS_BUILD_DIR:-build}"
# TIGRIS_CTEST_ARGS: extra ctest arguments, e.g. "-L quick" for the quick tier (docs/testing.md).
# shellcheck disable=SC2086
ctest --output-on-failure -j"$(nproc)" ${TIGRIS_CTEST_ARGS:-}
