#!/usr/bin/env bash
# Installs dependencies, builds dynrt and runs every test twice: once optimised, once under
# AddressSanitizer + UndefinedBehaviorSanitizer (tests named Heavy* are left to the first run).
# Then fuzzes the scene loaders for a bounded time (scripts/fuzz.sh, built with clang).
# Ends with one line "N passed, N failed" over every test case that ran (GoogleTest cases of
# both runs, the ctest-only tests, and each fuzz target as one test); a failing test does not
# stop the later runs, and the exit status is non-zero when any failed. A build failure stops
# the script at once.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh

DYNRT_TEST_TALLY=$(mktemp)
export DYNRT_TEST_TALLY
trap 'rm -f "$DYNRT_TEST_TALLY"' EXIT
status=0

bash scripts/build.sh release -DCMAKE_BUILD_TYPE=Release
bash scripts/install-python.sh build/release
bash scripts/run_tests.sh build/release || status=1

# -O1 with line tables only, as sanitizer builds usually are: reports still give file and line,
# and it compiles in well under half the time of -O2 -g (measured on three of the heaviest
# files: 67 -> 32 s, 47 -> 19 s, 48 -> 20 s), which was most of the test command's time.
bash scripts/build.sh asan -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1 -DNDEBUG" -DDYNRT_SANITIZE=ON \
  -DDYNRT_BUILD_BENCHMARKS=OFF
ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1 \
  bash scripts/run_tests.sh build/asan '-*Heavy*' || status=1

# Coverage-guided fuzzing of the scene loaders (scripts/fuzz.sh): the glTF loader for 30 s, the
# procedural and animation spec parsers and the BART (AFF) loader for 10 s each (their grammars
# are small, and coverage stops growing within seconds), each counted as one test: a crash fails it. On the 2-core development machine,
# shared and busy, the clang build took 3 min 15 s and the whole step 4 min; the build is most of
# it (tinygltf's implementation alone about 50 s of one core).
for run in "30 gltf_loader" "10 procedural_spec" "10 animation_specs" "10 aff_scene"; do
  set -- $run
  if bash scripts/fuzz.sh "$1" "$2"; then echo "1 0" >>"$DYNRT_TEST_TALLY"; else echo "0 1" >>"$DYNRT_TEST_TALLY"; status=1; fi
done

passed=$(awk '{ p += $1 } END { print p + 0 }' "$DYNRT_TEST_TALLY")
failed=$(awk '{ f += $2 } END { print f + 0 }' "$DYNRT_TEST_TALLY")
[ "$failed" -eq 0 ] || status=1
echo "$passed passed, $failed failed"
exit $status
