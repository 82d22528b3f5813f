#!/usr/bin/env bash
# CTest Docs.SiteBuildsAndShows (registered in tests/CMakeLists.txt):
#   bash docs_site.sh MKDOCS CHROMIUM REPO OUT
# Builds the user guide's site (mkdocs.yml) into OUT/site, opens its front page in headless
# Chromium, and checks what the browser shows: the guide's title and its map of pages in the
# rendered page, and a screenshot (OUT/site.png, to look at) that is not blank (issue 37).
set -euo pipefail
mkdocs=$1 chromium=$2 repo=$3 out=$4
rm -rf "$out" && mkdir -p "$out"
(cd "$repo" && "$mkdocs" build -q -f mkdocs.yml -d "$out/site")
page="file://$out/site/index.html"
flags=(--headless --no-sandbox --disable-gpu --hide-scrollbars --window-size=1280,900)
"$chromium" "${flags[@]}" --dump-dom "$page" > "$out/dom.html" 2> "$out/chromium.log"
"$chromium" "${flags[@]}" --screenshot="$out/site.png" "$page" >> "$out/chromium.log" 2>&1
for text in "user guide" "Rendering stills and animations" "Benchmarking" "The library API"; do
  grep -q "$text" "$out/dom.html" || { echo "docs_site: the rendered page lacks '$text'"; exit 1; }
done
size=$(stat -c %s "$out/site.png")
# A blank 1280x900 page compresses to a few kB; the guide's front page, text and table, to far more.
if [ "$size" -lt 30000 ]; then echo "docs_site: $out/site.png is $size bytes: a blank page?"; exit 1; fi
echo "docs_site: the guide renders; screenshot $out/site.png ($size bytes)"
