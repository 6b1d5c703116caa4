#!/usr/bin/env bash
# Rebuild the viewer's bundled libraries (a developer's step, never a user's: the wheel ships the
# result). npm installs the versions pinned in package.json / package-lock.json into a scratch
# folder; esbuild bundles what entry.js names into one minified script (a global HDV) and the
# licences of three.js and uPlot go next to it. Run from anywhere:  bash tools/viewer-vendor/build.sh
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
assets="$here/../../src/hosedrogue/viewer/assets"
scratch="$(mktemp -d)"
trap 'rm -rf "$scratch"' EXIT
cp "$here/package.json" "$here/package-lock.json" "$here/entry.js" "$scratch/"
cd "$scratch"
npm ci --no-audit --no-fund --loglevel=error
node_modules/.bin/esbuild entry.js --bundle --minify --format=iife --global-name=HDV --legal-comments=none \
  --target=es2020 --outfile="$assets/vendor.min.js" --log-level=warning
cp node_modules/uplot/dist/uPlot.min.css "$assets/vendor.min.css"
# a field of an installed package's package.json (read as a file: three's "exports" hide it from require)
field() { node -e 'const fs = require("fs"); process.stdout.write(String(JSON.parse(fs.readFileSync(
  "node_modules/" + process.argv[1] + "/package.json", "utf8"))[process.argv[2]]))' "$1" "$2"; }
{
  echo "The hosedrogue viewer bundles (vendor.min.js, vendor.min.css) these libraries, unmodified,"
  echo "minified together by esbuild $(field esbuild version) (tools/viewer-vendor/build.sh):"
  echo
  for pkg in three uplot; do
    echo "==== $pkg $(field "$pkg" version) ($(field "$pkg" license) licence) ===="
    cat "node_modules/$pkg/LICENSE"
    echo
  done
} > "$assets/THIRD-PARTY-LICENSES.txt"
ls -l "$assets"
