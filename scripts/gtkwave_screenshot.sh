#!/usr/bin/env bash
# Screenshots GTKWave opening a run's save file, headless (Xvfb), to check what a user sees.
# Usage: scripts/gtkwave_screenshot.sh RUN.gtkw OUT.png   (needs gtkwave, xvfb, imagemagick)
set -euo pipefail
gtkw=$1 out=$2
display=:$((90 + RANDOM % 100))
Xvfb "$display" -screen 0 1400x900x24 >/dev/null 2>&1 & xvfb=$!
trap 'kill $viewer $xvfb 2>/dev/null || true' EXIT
sleep 2
DISPLAY=$display gtkwave "$gtkw" >/dev/null 2>&1 & viewer=$!
sleep 6
DISPLAY=$display import -window root "$out"
echo "wrote $out"
