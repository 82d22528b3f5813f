#!/usr/bin/env bash
# Installs dependencies, builds dynrt and renders the bundled default scene: writes
# out/default.png (+ depth/object AOVs) and out/report.json, and prints the timing report.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
bash scripts/build.sh release -DCMAKE_BUILD_TYPE=Release -- dynrt
mkdir -p out
./build/release/engine/dynrt render --out out/default.png --aov depth,object \
  --report out/report.json "$@"
