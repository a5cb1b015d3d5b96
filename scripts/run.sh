#!/usr/bin/env bash
# The main job: builds, then runs the accelerator model on the built-in synthetic frame pair
# (default configuration: 64 RU, 32 SU x 32 PE, top height 10): exact NN, then radius 0.30,
# each checked query by query against the golden model. Arguments, if any, replace that and
# go to `tigris` as they are, e.g. scripts/run.sh ref --mode knn --k 8
set -euo pipefail
cd "$(dirname "$0")/.."
# Only the `tigris` program is needed here (scripts/test.sh builds the rest); its build output
# goes to build/run-build.log and is shown when the build fails.
scripts/deps.sh
if [ ! -f build/CMakeCache.txt ]; then
  echo "Configuring build/ (Release) ..." >&2
  cmake -S . -B build -DCMAKE_BUILD_TYPE=Release >/dev/null
  echo "Building tigris (a few minutes the first time) ..." >&2
fi
if ! cmake --build build --target tigris -j"$(nproc)" > build/run-build.log 2>&1; then
  cat build/run-build.log >&2
  exit 2
fi
tigris=build/bin/tigris
if [ $# -gt 0 ]; then exec "$tigris" "$@"; fi
"$tigris" run --mode nn --out tigris-out/nn
"$tigris" run --mode radius --radius 0.30 --out tigris-out/radius
