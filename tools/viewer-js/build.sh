#!/usr/bin/env bash
# Maintainer-only: rebuild the three.js bundle the armanim viewer page inlines.
#
#   tools/viewer-js/build.sh
#
# Installs the versions pinned in package.json / package-lock.json (three.js, esbuild)
# with npm into a temporary folder, bundles entry.js (the classes the page uses, as
# window.THREE) into one minified IIFE, and writes
#
#   src/armanim/render/viewer/assets/three-viewer.min.js    the bundle (three.js's MIT licence header kept)
#   src/armanim/render/viewer/assets/three-viewer.json      its three.js and esbuild versions, bytes and sha256
#
# Commit both. Users and CI never run this and never need node: the bundle is package
# data, and tests/render/test_viewer.py checks it against the recorded version and sha256.
# To move to another three.js: change the versions in package.json, run
# `npm install --package-lock-only` here, then this script, then the viewer tests.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
assets="$here/../../src/armanim/render/viewer/assets"
command -v npm >/dev/null || { echo "build.sh: needs node and npm on PATH" >&2; exit 1; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cp "$here/package.json" "$here/package-lock.json" "$here/entry.js" "$work/"
cd "$work"
npm ci --no-audit --no-fund --loglevel=error
three=$(node -p 'JSON.parse(require("fs").readFileSync("node_modules/three/package.json", "utf8")).version')
esbuild=$(./node_modules/.bin/esbuild --version)
./node_modules/.bin/esbuild entry.js --bundle --minify --format=iife --legal-comments=inline \
  --log-level=warning --outfile=three-viewer.min.js
mkdir -p "$assets"
cp three-viewer.min.js "$assets/three-viewer.min.js"
bytes=$(wc -c < three-viewer.min.js)
sha=$(sha256sum three-viewer.min.js | cut -d' ' -f1)
cat > "$assets/three-viewer.json" <<JSON
{
  "file": "three-viewer.min.js",
  "three": "$three",
  "esbuild": "$esbuild",
  "license": "MIT",
  "bytes": $bytes,
  "sha256": "$sha",
  "built_by": "tools/viewer-js/build.sh"
}
JSON
echo "wrote $assets/three-viewer.min.js ($bytes bytes, three $three, esbuild $esbuild, sha256 $sha)"
