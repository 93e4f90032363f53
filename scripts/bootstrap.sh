#!/usr/bin/env bash
# The README's first command: install what rostro needs, build it (Release, into build/),
# and run the main job on the bundled sample data.
set -euo pipefail
cd "$(dirname "$0")/.."

bash scripts/install-deps.sh
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release
cmake --build build -j"$(nproc)"
bash scripts/main-job.sh
