#!/usr/bin/env bash
# Installs dependencies, builds dynrt and renders the bundled default scene twice:
#   1. an animated sequence, the product: 48 frames in which the ground ripples (wave: a refit
#      every frame), the torus and the upper box turn (rigid: only their instances move) and
#      the green icosphere flies apart (explode: refits, rebuilt when they degrade), written as
#      out/animation.gif and out/contact_sheet.png with its per-frame report
#      out/sequence.json; the table shows the first (cold) frame beside the steady-state
#      frames after it;
#   2. a still frame: out/default.png (+ depth/object AOVs) and out/report.json.
# It also builds the Python module and makes `import dynrt` work (scripts/install-python.sh).
# Extra arguments go to both renders (e.g. --res 1920x1080).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
bash scripts/build.sh release -DCMAKE_BUILD_TYPE=Release -- dynrt dynrt_python
# `import dynrt` from Debian's python3 from now on (docs/python.md "Python").
bash scripts/install-python.sh build/release
mkdir -p out
dynrt=./build/release/engine/dynrt
motions=(--anim wave:ground --anim rigid:blue_torus --anim rigid:box_top
         --anim explode:green_icosphere)
echo "== animated sequence: 48 frames of the bundled scene"
"$dynrt" render --frames 0-47 "${motions[@]}" --res 512x512 \
  --out out/animation.gif --contact-sheet out/contact_sheet.png --report out/sequence.json "$@"
echo
echo "== still frame"
"$dynrt" render --out out/default.png --aov depth,object --report out/report.json "$@"
