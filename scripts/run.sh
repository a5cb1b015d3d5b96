#!/usr/bin/env bash
# The main job: builds, then runs the accelerator model on the built-in synthetic frame pair
# (default configuration: 64 RU, 32 SU x 32 PE, top height 10): exact NN, then radius 0.30,
# each checked query by query against the golden model. Arguments, if any, replace that and
# go to `tigris` as they are, e.g. scripts/run.sh ref --mode knn --k 8
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/build.sh
tigris=build/testbench/tigris
if [ $# -gt 0 ]; then exec "$tigris" "$@"; fi
"$tigris" run --mode nn --out tigris-out/nn
"$tigris" run --mode radius --radius 0.30 --out tigris-out/radius
