#!/usr/bin/env bash
# The BART benchmark (README.md, "BART"): every frame of kitchen, robots and museum at 1024x1024
# with shadows, dynrt beside Embree 3 (both of its per-frame update modes) on the same frames,
# cameras and rays, in one process per scene. Reads the scenes from ../shared/scenes/bart (or
# BART_DIR); skips a scene that is not there. Writes each table to stdout and each scene's rows
# and per-frame report to build/bart/<scene>.json.
#   bash benchmarks/bart.sh [extra dynrt bench options...]
set -euo pipefail
cd "$(dirname "$0")/.."
bart=${BART_DIR:-../shared/scenes/bart}
extra=("$@")
bash scripts/install-deps.sh
bash scripts/build.sh release -DCMAKE_BUILD_TYPE=Release -- dynrt
mkdir -p build/bart
for scene in "kitchen kitchen/kitchen.aff 0-799" "robots robots/Robot.aff 0-799" \
             "museum museum/museum5.aff 0-299"; do
  set -- $scene
  if [ ! -f "$bart/$2" ]; then
    echo "bart: $bart/$2 not found, skipping $1" >&2
    continue
  fi
  ./build/release/engine/dynrt bench "$bart/$2" --frames "$3" --res 1024x1024 --vs embree \
    --json "build/bart/$1.json" "${extra[@]}"
done
