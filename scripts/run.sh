#!/usr/bin/env bash
# Installs dependencies, builds dynrt and renders the bundled default scene twice:
#   1. an animated sequence, the product: 48 frames in which the six moons orbit (rigid) and
#      the ground ripples (wave, refitted every frame), written as out/animation.gif and
#      out/contact_sheet.png with its per-frame report out/sequence.json; the table shows the
#      first (cold) frame beside the steady-state frames after it;
#   2. a still frame: out/default.png (+ depth/object AOVs) and out/report.json.
# Extra arguments go to both renders (e.g. --res 1920x1080).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
bash scripts/build.sh release -DCMAKE_BUILD_TYPE=Release -- dynrt
mkdir -p out
dynrt=./build/release/engine/dynrt
motions=()
for moon in 0 1 2 3 4 5; do motions+=(--anim "rigid:moon$moon"); done
echo "== animated sequence: 48 frames of the bundled scene"
"$dynrt" render --frames 48 "${motions[@]}" --anim wave:ground --res 512x512 \
  --out out/animation.gif --contact-sheet out/contact_sheet.png --report out/sequence.json "$@"
echo
echo "== still frame"
"$dynrt" render --out out/default.png --aov depth,object --report out/report.json "$@"
