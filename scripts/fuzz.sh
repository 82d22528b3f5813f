#!/usr/bin/env bash
# Builds the fuzz configuration (clang, libFuzzer, ASan+UBSan; only the scene loaders) into
# build/fuzz and runs each fuzz target of fuzz/ for SECONDS seconds (default 30), one after the
# other. Fails on the first crash, hang, leak or sanitizer report, leaving the input in
# build/fuzz/crashes/. The corpus each run grows is kept in build/fuzz/corpus/<target>/, so a
# later run continues where the last one stopped; the seeds stay in fuzz/corpus/<target>/.
#   scripts/fuzz.sh [SECONDS [TARGET...]]      targets: gltf_loader procedural_spec animation_specs aff_scene
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-30}
[ $# -gt 0 ] && shift
targets=("$@")
[ ${#targets[@]} -gt 0 ] || targets=(gltf_loader procedural_spec animation_specs aff_scene)

# -O1 with line tables only, as fuzzing builds usually are: it compiles faster than -O2 -g
# (tinygltf's implementation dominates the build), and sanitizer reports still give file and
# line.
bash scripts/build.sh fuzz -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -gline-tables-only -DNDEBUG" \
  -DCMAKE_CXX_COMPILER=clang++ -DDYNRT_FUZZ=ON -- "${targets[@]/%/_fuzz}"

mkdir -p build/fuzz/crashes
for target in "${targets[@]}"; do
  corpus=build/fuzz/corpus/$target
  log=build/fuzz/$target.log
  mkdir -p "$corpus"
  # -timeout: one input running 10 s is a hang. -max_len: room for small documents with their
  # buffers (the glTF seeds are at most 2 kB). The full log goes to a file: libFuzzer prints a
  # line for every new input.
  if ! ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1 \
      "build/fuzz/fuzz/${target}_fuzz" -max_total_time="$seconds" -timeout=10 -max_len=8192 \
      -dict="fuzz/$target.dict" -artifact_prefix="build/fuzz/crashes/$target-" -print_final_stats=1 \
      "$corpus" "fuzz/corpus/$target" >"$log" 2>&1; then
    tail -n 60 "$log" >&2
    echo "fuzz: $target failed (log: $log). A crash leaves its input in build/fuzz/crashes/: fix the" \
         "engine, then keep the input in tests/data/fuzz_regressions/$target/ (README.md, \"Fuzzing\")" >&2
    exit 1
  fi
  echo "fuzz: $target: $(grep -E '^#[0-9]+[[:space:]]+DONE' "$log" | tail -n 1)"
done
