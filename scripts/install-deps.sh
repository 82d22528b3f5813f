#!/usr/bin/env bash
# Installs dynrt's build and test dependencies from Debian/Ubuntu packages. Idempotent and
# non-interactive: does nothing when everything is already there.
set -euo pipefail

required=(build-essential cmake ninja-build pkg-config ccache
          libglm-dev libtinygltf-dev nlohmann-json3-dev libstb-dev libtbb-dev
          libopenimageio-dev libbenchmark-dev libgtest-dev libcli11-dev
          libassimp-dev  # OBJ, PLY, FBX, Collada... scene files (engine/src/loaders/assimp_loader.cpp)
          libmeshoptimizer-dev  # the simplified meshes of --lod (engine/src/rendering/simplified_levels.cpp)
          gnuplot-nox   # gnuplot draws the charts of `dynrt bench --plot`
          pybind11-dev python3-dev python3-numpy python3-pytest  # the Python module (engine/python)
          doxygen mkdocs)  # the API reference and the guide's site (scripts/docs.sh, their tests)
# The fuzz targets (scripts/fuzz.sh, run by scripts/test.sh) need clang and libFuzzer's runtime,
# which Debian ships in libclang-rt-dev; older archives have it in a dependency of clang itself.
fuzz=(clang libclang-rt-dev)
# Embree is only a comparison backend and test oracle; Open MPI lets `mpirun dynrt render`
# spread frames or tiles across processes (engine/mpi); the ffmpeg program writes `--out
# anim.mp4` (and the video tests run with it). Installed when the archive has them.
# Chromium opens the guide's site in a test (Docs.SiteBuildsAndShows).
# GLFW and Dear ImGui give `dynrt view` its window; xvfb-run lets its tests open one headless.
optional=(libembree-dev libopenmpi-dev openmpi-bin ffmpeg chromium fonts-liberation
          libglfw3-dev libimgui-dev xvfb xauth libgl1-mesa-dri)

missing=()
for p in "${required[@]}" "${fuzz[@]}" "${optional[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
[ ${#missing[@]} -eq 0 ] && exit 0

sudo=""
if [ "$(id -u)" -ne 0 ]; then
  command -v sudo >/dev/null || { echo "install-deps: need root or sudo to install: ${missing[*]}" >&2; exit 1; }
  sudo="sudo"
fi
export DEBIAN_FRONTEND=noninteractive
echo "install-deps: installing ${missing[*]}"
$sudo apt-get update -qq
$sudo apt-get install -y -qq --no-install-recommends "${required[@]}" >/dev/null
$sudo apt-get install -y -qq --no-install-recommends "${fuzz[@]}" >/dev/null \
  || $sudo apt-get install -y -qq --no-install-recommends clang >/dev/null
$sudo apt-get install -y -qq --no-install-recommends libembree-dev >/dev/null \
  || echo "install-deps: optional libembree-dev not available; Embree comparisons are skipped"
$sudo apt-get install -y -qq --no-install-recommends libopenmpi-dev openmpi-bin >/dev/null \
  || echo "install-deps: optional Open MPI not available; dynrt is built without MPI and its tests are skipped"
$sudo apt-get install -y -qq --no-install-recommends ffmpeg >/dev/null \
  || echo "install-deps: optional ffmpeg not available; video output is refused and its tests are skipped"
$sudo apt-get install -y -qq --no-install-recommends libglfw3-dev libimgui-dev xvfb xauth libgl1-mesa-dri >/dev/null \
  || echo "install-deps: optional GLFW, Dear ImGui or Xvfb not available; dynrt view has no window and its window tests are skipped"
$sudo apt-get install -y -qq --no-install-recommends chromium fonts-liberation >/dev/null \
  || echo "install-deps: optional chromium not available; the test that opens the guide's site is skipped"
