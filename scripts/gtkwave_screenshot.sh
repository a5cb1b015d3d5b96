#!/usr/bin/env bash
# Screenshots GTKWave opening a run's save file, headless (Xvfb), to check what a user sees.
# Usage: scripts/gtkwave_screenshot.sh RUN.gtkw OUT.png [TIMEOUT_S]
# (needs gtkwave, xvfb, imagemagick, xdotool). GTKWave shows a splash screen while it reads the
# dump (tens of seconds for a KITTI-sized VCD), so the picture is taken once its main window is
# up and the screen has not changed for two seconds; after TIMEOUT_S (default 300) it gives up
# with exit 1 rather than capture a half-loaded window.
set -euo pipefail
gtkw=$1 out=$2 timeout=${3:-300}
[ -f "$gtkw" ] || { echo "$0: no such save file: $gtkw" >&2; exit 2; }
display=:$((90 + RANDOM % 100))
tmp=$(mktemp -d)
Xvfb "$display" -screen 0 1400x900x24 >/dev/null 2>&1 & xvfb=$!
viewer=""
trap 'kill $viewer $xvfb 2>/dev/null || true; rm -rf "$tmp"' EXIT
sleep 1
DISPLAY=$display gtkwave "$gtkw" >"$tmp/gtkwave.log" 2>&1 & viewer=$!
start=$(date +%s) prev="" stable=0
while :; do
  sleep 1
  kill -0 "$viewer" 2>/dev/null || { echo "$0: gtkwave exited: $(tail -3 "$tmp/gtkwave.log")" >&2; exit 1; }
  if DISPLAY=$display xdotool search --onlyvisible --name "^GTKWave - " >/dev/null 2>&1; then
    DISPLAY=$display import -window root "$tmp/shot.png"
    sum=$(convert "$tmp/shot.png" rgb:- | md5sum)
    if [ "$sum" = "$prev" ]; then stable=$((stable + 1)); else stable=0; fi
    prev=$sum
    if [ "$stable" -ge 2 ]; then break; fi
  fi
  if [ $(( $(date +%s) - start )) -ge "$timeout" ]; then
    echo "$0: GTKWave had not settled after ${timeout} s; no screenshot" >&2
    exit 1
  fi
done
cp "$tmp/shot.png" "$out"
echo "wrote $out ($(( $(date +%s) - start )) s after starting GTKWave)"
