#!/usr/bin/env bash
# The main job on bundled sample data, run by scripts/bootstrap.sh: capture an actor's take
# to MPEG-4 FAPs. The take (data/samples/take.mp4) was rendered by rostro itself:
#   rostro synth -o data/samples/take --seconds 5 --neutral-lead 1 --noise 2 --seed 3
# so the FAPs that drove it (data/samples/take.fap) score the capture. Outputs go to out/.
set -euo pipefail
cd "$(dirname "$0")/.."
mkdir -p out

build/rostro capture data/samples/take.mp4 --layout data/layouts/default.json \
  --camera data/samples/take.intrinsics.yml -o out/take.fap --tracks out/take.tracks.csv \
  --preview out/take-preview.mp4
build/rostro eval faps --truth data/samples/take.fap --est out/take.fap --faps 3,59,31 \
  --plot out/take-faps.png
echo "main job done: out/take.fap (FAPs), out/take-preview.mp4 (markers beside the head),"
echo "out/take-faps.png (captured against driving FAPs)"
