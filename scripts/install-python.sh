#!/usr/bin/env bash
# Makes `import dynrt` work for Debian's python3 (the interpreter with Debian's numpy, which the
# module is built for): writes a dynrt.pth file into its per-user site-packages folder naming
# BUILD_DIR/python, where the build assembles the package (engine/python/CMakeLists.txt). No
# root needed, nothing copied: a rebuild updates the module in place. Run by scripts/run.sh and
# scripts/test.sh after building; `rm "$(python3 -m site --user-site)/dynrt.pth"` undoes it.
#   scripts/install-python.sh BUILD_DIR
set -euo pipefail
cd "$(dirname "$0")/.."
dir=$(cd "$1" && pwd)
python=$(sed -n 's/^DYNRT_PYTHON_EXECUTABLE:INTERNAL=//p' "$dir/CMakeCache.txt" 2>/dev/null || true)
if [ -z "$python" ] || [ ! -f "$dir/python/dynrt/__init__.py" ]; then
  echo "install-python: no Python module in $dir (pybind11 or python3-dev missing?); skipped" >&2
  exit 0
fi
site=$("$python" -m site --user-site)
if [ "$("$python" -c 'import site; print(site.ENABLE_USER_SITE)')" != "True" ]; then
  echo "install-python: $python has per-user site-packages disabled; use PYTHONPATH=$dir/python" >&2
  exit 0
fi
mkdir -p "$site"
echo "$dir/python" >"$site/dynrt.pth"
"$python" -c "import dynrt" || { echo "install-python: import dynrt failed with $python" >&2; exit 1; }
echo "install-python: import dynrt works with $python ($site/dynrt.pth -> $dir/python)"
