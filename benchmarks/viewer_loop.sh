#!/usr/bin/env bash
# What `dynrt view` adds to a frame, and its input-to-photon latency (issue 42's targets): the
# window is driven under xvfb-run by a script that orbits the camera one degree per frame for
# FRAMES frames (so every frame is traced in full: exact reuse keeps nothing while the camera
# moves), the panels shown, at 640x480 on the bundled scene unless told otherwise. The viewer
# prints, when it closes, the frames' render time, its own work per frame besides (bytes,
# drawing, panels, swap) and the time from each scripted input to the swap showing it.
#
#   bash benchmarks/viewer_loop.sh [DYNRT] [FRAMES] [on|off: the panels] [extra view flags...]
set -euo pipefail
dynrt=${1:-build/release/engine/dynrt}
frames=${2:-120}
panels=${3:-on}
shift $(( $# > 3 ? 3 : $# ))
script=$(mktemp)
trap 'rm -f "$script"' EXIT
echo "0 overlay $panels" > "$script"
echo "0 wait-frames 5" >> "$script"
for _ in $(seq "$frames"); do
  echo "0 orbit 1 0" >> "$script"
  echo "0 wait-frames 1" >> "$script"
done
echo "0 quit" >> "$script"
xvfb-run -a -s "-screen 0 1280x1024x24" "$dynrt" view --res 640x480 --script "$script" "$@"
