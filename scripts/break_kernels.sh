#!/usr/bin/env bash
# Breaks the trace kernels on purpose, one way at a time, and checks that the test suites
# notice: each break is applied to the source, the tests are built and run, and the break is
# undone (also on Ctrl-C). A break that no test catches is reported, and the script then
# exits 1. Run it after changing a kernel, to show the tests can still fail:
#
#   bash scripts/break_kernels.sh            # every break (about 3 minutes each on 2 cores)
#   bash scripts/break_kernels.sh octant     # the breaks whose name contains "octant"
#
# It builds into build/release (the optimised build of scripts/test.sh) and leaves the
# sources as they were. Not part of scripts/test.sh: it rebuilds once per break.
set -uo pipefail
cd "$(dirname "$0")/.."

only="${1:-}"

# Each break: a name, the file, the text to replace (it must occur exactly once) and the
# replacement, as a function that sets them (texts may hold any character).
break_1() {
  name="single-ray any-hit exit reports a miss"
  file=bvh/src/wide_traversal.cpp
  old=$'                if constexpr (kAnyHit) {\n                    return true;'
  new=$'                if constexpr (kAnyHit) {\n                    return false;'
}
break_2() {
  name="packet any-hit ends every live lane of a chunk at one hit"
  file=packet/src/range_tracer.h
  old='            hits |= hit;'
  new='            hits |= hit != 0 ? live : 0u;'
}
break_3() {
  name="single-ray octant 1 traced with octant 3's near and far planes"
  file=bvh/src/wide_traversal.cpp
  old='        case 1: return traverse<N, kAnyHit, kCount, 1>'
  new='        case 1: return traverse<N, kAnyHit, kCount, 3>'
}
break_4() {
  name="wide refit keeps a leaf's old vertices"
  file=bvh/src/wide_refit.cpp
  old='                    block.v0[axis][lane] = t.v0[axis];'
  new='                    if (false) block.v0[axis][lane] = t.v0[axis];'
}
break_5() {
  name="static-group hit attributed within one bucket too few"
  file=engine/src/update/scene_accel.h
  old='std::upper_bound(from, to, hit.hit.prim)'
  new='std::upper_bound(from, to - 1, hit.hit.prim)'
}
kBreaks=5

current_file=""
restore() {
  if [[ -n "$current_file" ]]; then
    git checkout -q -- "$current_file"
    current_file=""
  fi
}
trap restore EXIT INT TERM

if ! git diff --quiet -- bvh packet engine; then
  echo "break_kernels: bvh/, packet/ or engine/ has uncommitted changes; commit or stash them first" >&2
  exit 2
fi

missed=0
ran=0
for ((k = 1; k <= kBreaks; ++k)); do
  "break_$k"
  if [[ -n "$only" && "$name" != *"$only"* ]]; then continue; fi
  ran=$((ran + 1))
  current_file="$file"
  if ! python3 - "$file" "$old" "$new" <<'PY'; then
import sys
path, old, new = sys.argv[1:4]
text = open(path).read()
if text.count(old) != 1:
    sys.exit(f"break_kernels: the text to break occurs {text.count(old)} times in {path}")
open(path, "w").write(text.replace(old, new))
PY
    restore
    echo "FAIL (could not apply): $name"
    missed=$((missed + 1))
    continue
  fi
  if ! bash scripts/build.sh release -DCMAKE_BUILD_TYPE=Release -- dynrt_tests dynrt_stress_tests dynrt_api_tests \
      >/tmp/break_kernels_build_$ran.log 2>&1; then
    restore
    echo "FAIL (does not build; see /tmp/break_kernels_build_$ran.log): $name"
    missed=$((missed + 1))
    continue
  fi
  caught=()
  for suite in tests/dynrt_tests tests/dynrt_stress_tests tests/api/dynrt_api_tests; do
    "build/release/$suite" --gtest_brief=1 >/tmp/break_kernels_run.log 2>&1
    status=$?
    if ((status > 128)); then
      caught+=("$(basename "$suite"): crashed")
    elif ((status != 0)); then
      caught+=("$(basename "$suite"): $(grep -c '^\[  FAILED  \] [A-Za-z]' /tmp/break_kernels_run.log) failed")
    fi
  done
  restore
  if ((${#caught[@]} == 0)); then
    echo "MISSED: $name (every test passed)"
    missed=$((missed + 1))
  else
    echo "caught: $name (${caught[*]})"
  fi
done

# Leave the build matching the restored sources.
bash scripts/build.sh release -DCMAKE_BUILD_TYPE=Release -- dynrt_tests dynrt_stress_tests dynrt_api_tests \
  >/tmp/break_kernels_build.log 2>&1
echo "$ran breaks, $((ran - missed)) caught, $missed missed"
((missed == 0))
