#!/usr/bin/env bash
# Runs the tests of one build tree: each GoogleTest program once, split into as many shards as
# there are cores run side by side, then ctest for the tests that are not GoogleTest cases
# (label gtest: examples, the docs/library-api.md check, the installed-package build), then the Python
# module's pytest suite (tests/python) when the tree built the module.
# With DYNRT_TEST_TALLY set to a file, appends a line "PASSED FAILED" per program and one for
# ctest, which scripts/test.sh sums into its closing summary line.
#   scripts/run_tests.sh BUILD_DIR [GTEST_FILTER]
# `ctest --test-dir BUILD_DIR` runs the very same tests, one process per case, which is handier
# for picking tests (-R) but slow for all of them: starting a test process costs about 0.4 s in
# the optimised build and 1 s under ASan (the engine's libraries load and initialise), so for
# 430 cases process start-up was most of the suite's time (88 s and 219 s on 2 cores; one
# process per program and shard ran the 381 cases of dynrt_tests in 22 s).
set -euo pipefail
dir=$1
filter=${2:-*}
shards=$(nproc)

failed=0
tally() { [ -n "${DYNRT_TEST_TALLY:-}" ] && echo "$1 $2" >>"$DYNRT_TEST_TALLY"; return 0; }
for program in tests/dynrt_tests tests/dynrt_stress_tests tests/api/dynrt_api_tests; do
  folder="$dir/$(dirname "$program")"
  name=$(basename "$program")
  pids=()
  for ((shard = 0; shard < shards; ++shard)); do
    (cd "$folder" && GTEST_TOTAL_SHARDS=$shards GTEST_SHARD_INDEX=$shard \
       timeout 1800 "./$name" --gtest_brief=1 --gtest_filter="$filter" >"$name.shard$shard.log" 2>&1) &
    pids+=($!)
  done
  for ((shard = 0; shard < shards; ++shard)); do
    log="$folder/$name.shard$shard.log"
    if wait "${pids[$shard]}"; then
      echo "$name shard $shard/$shards: $(grep -E '^\[==========\]' "$log" | tail -n 1)"
    else
      tail -n 80 "$log" >&2
      echo "$name shard $shard/$shards FAILED (log: $log)" >&2
      failed=1
    fi
    # GoogleTest's own counts: the passed from its summary, the failed one per "[  FAILED  ]
    # Name (N ms)" line (with --gtest_brief=1 the summary has no failed count). A shard that
    # died before printing its summary counts as one failure more.
    shard_passed=$(sed -n 's/^\[  PASSED  \] \([0-9]*\) tests\{0,1\}\..*/\1/p' "$log" | tail -n 1)
    shard_failed=$(grep -cE '^\[  FAILED  \] .* \([0-9]+ ms\)$' "$log" || true)
    if [ -z "$shard_passed" ]; then shard_failed=$((shard_failed + 1)); fi
    tally "${shard_passed:-0}" "${shard_failed:-0}"
  done
done
ctest_log=$(mktemp)
ctest --test-dir "$dir" --output-on-failure -j "$shards" -LE gtest | tee "$ctest_log" || failed=1
# "100% tests passed, 0 tests failed out of 5"
read -r ctest_failed ctest_total < <(sed -n 's/.*tests passed, \([0-9]*\) tests\{0,1\} failed out of \([0-9]*\).*/\1 \2/p' "$ctest_log" | tail -n 1) || true
rm -f "$ctest_log"
if [ -n "${ctest_total:-}" ]; then tally $((ctest_total - ctest_failed)) "$ctest_failed"; else tally 0 1; fi

# pytest, with the interpreter the module was built for; each test case counts. Its summary
# line reads e.g. "3 failed, 61 passed, 2 skipped in 31.2s": skipped tests did not run, errors
# (a fixture or collection failing) count as failed.
python=$(sed -n 's/^DYNRT_PYTHON_EXECUTABLE:INTERNAL=//p' "$dir/CMakeCache.txt" 2>/dev/null || true)
if [ -n "$python" ] && [ -f "$dir/python/dynrt/__init__.py" ]; then
  pytest_env=(PYTHONPATH="$(cd "$dir" && pwd)/python"
              DYNRT_API_ORACLE="$(cd "$dir" && pwd)/tests/python/dynrt_python_api_oracle"
              DYNRT_CLI="$(cd "$dir" && pwd)/engine/dynrt")
  pytest_args=()
  if grep -q '^DYNRT_SANITIZE:BOOL=ON' "$dir/CMakeCache.txt"; then
    # The interpreter is not built with the sanitizers: their runtimes are preloaded for the
    # module and libdynrt. Leak checking is off for the Python process (the interpreter keeps
    # its own objects to the end by design); tests marked heavy (timing-based and long
    # ones) are left to the optimised run, as the GoogleTest Heavy* cases are.
    pytest_env+=(LD_PRELOAD="$(gcc -print-file-name=libasan.so) $(gcc -print-file-name=libubsan.so)"
                 ASAN_OPTIONS="detect_leaks=0:abort_on_error=1")
    pytest_args+=(-m "not heavy")
  fi
  pytest_log=$(mktemp)
  env "${pytest_env[@]}" timeout 1200 "$python" -m pytest -q -p no:cacheprovider "${pytest_args[@]}" \
    tests/python 2>&1 | tee "$pytest_log" || failed=1
  summary=$(tail -n 1 "$pytest_log")
  rm -f "$pytest_log"
  count() { echo "$summary" | grep -oE "[0-9]+ $1" | grep -oE '^[0-9]+' || echo 0; }
  py_passed=$(count passed); py_failed=$(( $(count failed) + $(count error) ))
  if [ "$py_passed" -eq 0 ] && [ "$py_failed" -eq 0 ]; then py_failed=1; fi  # pytest did not run
  tally "$py_passed" "$py_failed"
else
  echo "run_tests: $dir has no Python module; tests/python skipped"
fi
exit $failed
