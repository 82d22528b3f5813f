#!/usr/bin/env bash
# Configures and builds one flavour of dynrt into build/<name>.
#   scripts/build.sh NAME [cmake options...] [-- targets...]
set -euo pipefail
cd "$(dirname "$0")/.."
# ccache (when installed) keys on paths relative to the checkout, so that another clone of the
# same sources (CI's) finds what this one compiled.
export CCACHE_BASEDIR="${CCACHE_BASEDIR:-$PWD}"
name=$1; shift
opts=(); targets=()
while [ $# -gt 0 ]; do
  if [ "$1" = "--" ]; then shift; targets=("$@"); break; fi
  opts+=("$1"); shift
done
cmake -S . -B "build/$name" -G Ninja "${opts[@]}" >/dev/null
if [ ${#targets[@]} -gt 0 ]; then
  cmake --build "build/$name" -j "$(nproc)" --target "${targets[@]}"
else
  cmake --build "build/$name" -j "$(nproc)"
fi
