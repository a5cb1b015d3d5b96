#!/usr/bin/env bash
# The main job: builds, then runs the default testbench on the built-in synthetic frame pair.
# Extra arguments are passed to `tigris ref`.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/build.sh
exec build/testbench/tigris ref "$@"
