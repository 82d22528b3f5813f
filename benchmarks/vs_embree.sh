#!/usr/bin/env bash
# The trace core against Embree 3 used at its best (issue 17's yardstick): still frames of the
# four target scenes at 1024x1024 on all cores, dynrt's packet tracer and its single-ray
# tracer (on the wide tree, and again on the binary tree: --bvh binary) each in one
# `dynrt bench --vs embree` process beside Embree's three build qualities
# (rtcIntersect1/16 and rtcOccluded1/16, 16-ray packets of 4x4 pixels, coherent context). The
# two processes of a scene run back to back, so load on a shared machine falls on both.
# MetalRoughSpheresNoTextures is read from ../shared/scenes (or SCENES_DIR) and skipped when
# absent. Writes each run's rows to build/vs_embree/<scene>-<run>.json (run: packet, single,
# single-binary).
#   bash benchmarks/vs_embree.sh [extra dynrt bench options...]
set -euo pipefail
cd "$(dirname "$0")/.."
shared=${SCENES_DIR:-../shared/scenes}
extra=("$@")
bash scripts/install-deps.sh
bash scripts/build.sh release -DCMAKE_BUILD_TYPE=Release -- dynrt
mkdir -p build/vs_embree
scenes=("sphere sphere:1000000" "soup soup:1000000" "default scenes/default.gltf"
        "metalrough $shared/metalroughspheresnotextures/MetalRoughSpheresNoTextures.glb")
for entry in "${scenes[@]}"; do
  set -- $entry
  case "$2" in
    *.glb | *.gltf)
      if [ ! -f "$2" ]; then echo "vs_embree: $2 not found, skipping $1" >&2; continue; fi ;;
  esac
  for run in packet single single-binary; do
    tracer=${run%-binary}
    bvh=wide; [ "$run" = single-binary ] && bvh=binary
    echo "== $1, dynrt $tracer tracer, $bvh tree"
    ./build/release/engine/dynrt bench "$2" --res 1024x1024 --repeat 7 --tracer "$tracer" \
      --bvh "$bvh" --vs embree --json "build/vs_embree/$1-$run.json" "${extra[@]}"
  done
done
