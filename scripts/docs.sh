#!/usr/bin/env bash
# Builds the documentation into build/docs/: the library API's reference from its public headers
# (Doxygen, docs/Doxyfile: build/docs/api/index.html) and the user guide as a static site
# (MkDocs, mkdocs.yml: build/docs/site/index.html). Fails when Doxygen warns, as the test
# Docs.ApiReferenceIsComplete does. Installs the tools first (scripts/install-deps.sh).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
out=build/docs
rm -rf "$out/api" "$out/site" && mkdir -p "$out"
DYNRT_DOCS_OUT="$out" doxygen docs/Doxyfile
if [ -s "$out/doxygen-warnings.log" ]; then
  cat "$out/doxygen-warnings.log" >&2
  echo "docs: Doxygen warns about the API headers (above)" >&2
  exit 1
fi
mkdocs build -q -f mkdocs.yml -d "$out/site"
echo "docs: API reference $out/api/index.html"
echo "docs: user guide    $out/site/index.html"
