#!/usr/bin/env bash
# Installs dependencies, builds dynrt and runs every test twice: once optimised, once under
# AddressSanitizer + UndefinedBehaviorSanitizer (tests named Heavy* are left to the first run).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
jobs=$(nproc)

bash scripts/build.sh release -DCMAKE_BUILD_TYPE=Release
ctest --test-dir build/release --output-on-failure -j "$jobs"

bash scripts/build.sh asan -DCMAKE_BUILD_TYPE=RelWithDebInfo -DDYNRT_SANITIZE=ON \
  -DDYNRT_BUILD_BENCHMARKS=OFF
ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1 \
  ctest --test-dir build/asan --output-on-failure -j "$jobs" -E 'Heavy'
