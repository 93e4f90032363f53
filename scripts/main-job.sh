#!/usr/bin/env bash
# The main job on bundled sample data, run by scripts/bootstrap.sh: describe the bundled
# sample FAP stream. Outputs go to out/.
set -euo pipefail
cd "$(dirname "$0")/.."
mkdir -p out

build/rostro fap info data/samples/wave.fap
