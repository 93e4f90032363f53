#!/usr/bin/env bash
# The window's frame rate on this machine's OpenGL (llvmpipe without a GPU): `rostro play
# --window` under Xvfb on a 10 s stream at 120 fps, held to one core. play shows the frame
# the clock is at each time the window is ready and skips the rest, so frames shown / 10 s
# is the rate the window keeps. Sizes 640x480 and 1280x720, with multisampling (4, the
# default) and without (--samples 1). Run it when nothing else runs (it says the load).
#   bash bench/render/window_rate.sh [build-dir]
set -euo pipefail
cd "$(dirname "$0")/../.."
rostro=$(realpath "${1:-build}")/rostro
for tool in Xvfb taskset; do
  command -v "$tool" >/dev/null || { echo "$tool not installed (scripts/install-deps.sh)"; exit 1; }
done
work=$(mktemp -d)
trap 'kill "$xvfb" 2>/dev/null || true; rm -rf "$work"' EXIT
"$rostro" fap generate --seconds 10 --fps 120 -o "$work/stream.fap" >/dev/null
# A free display: Xvfb writes the number it took to fd 3.
Xvfb -displayfd 3 -screen 0 1920x1080x24 3>"$work/display" >/dev/null 2>&1 &
xvfb=$!
for _ in $(seq 50); do [ -s "$work/display" ] && break; sleep 0.1; done
display=":$(cat "$work/display")"
echo "load average: $(cut -d' ' -f1-3 /proc/loadavg); $(nproc) cores; one used"
echo
echo "| size | samples | frames shown in 10 s | window fps |"
echo "|---|---|---|---|"
for size in 640x480 1280x720; do
  for samples in 4 1; do
    line=$(DISPLAY=$display taskset -c 1 "$rostro" play "$work/stream.fap" --window \
      --width "${size%x*}" --height "${size#*x}" --samples "$samples" 2>/dev/null | tail -1)
    shown=$(sed -E 's/^played ([0-9]+) of.* to ([0-9.]+) s.*/\1/' <<<"$line")
    seconds=$(sed -E 's/^played ([0-9]+) of.* to ([0-9.]+) s.*/\2/' <<<"$line")
    echo "| $size | $samples | $shown | $(awk "BEGIN{printf \"%.1f\", $shown/$seconds}") |"
  done
done
