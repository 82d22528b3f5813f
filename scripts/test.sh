#!/usr/bin/env bash
# Installs dependencies, builds dynrt and runs every test twice: once optimised, once under
# AddressSanitizer + UndefinedBehaviorSanitizer (tests named Heavy* are left to the first run).
# Then fuzzes the scene loaders for a bounded time (scripts/fuzz.sh, built with clang).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh

bash scripts/build.sh release -DCMAKE_BUILD_TYPE=Release
bash scripts/run_tests.sh build/release

# -O1 with line tables only, as sanitizer builds usually are: reports still give file and line,
# and it compiles in well under half the time of -O2 -g (measured on three of the heaviest
# files: 67 -> 32 s, 47 -> 19 s, 48 -> 20 s), which was most of the test command's time.
bash scripts/build.sh asan -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1 -DNDEBUG" -DDYNRT_SANITIZE=ON \
  -DDYNRT_BUILD_BENCHMARKS=OFF
ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1 \
  bash scripts/run_tests.sh build/asan '-*Heavy*'

# Coverage-guided fuzzing of the scene loaders (scripts/fuzz.sh): the glTF loader for 30 s, the
# procedural and animation spec parsers and the BART (AFF) loader for 10 s each (their grammars
# are small, and coverage stops growing within seconds). A crash fails the script. On the 2-core development machine,
# shared and busy, the clang build took 3 min 15 s and the whole step 4 min; the build is most of
# it (tinygltf's implementation alone about 50 s of one core).
bash scripts/fuzz.sh 30 gltf_loader
bash scripts/fuzz.sh 10 procedural_spec animation_specs aff_scene
