#!/usr/bin/env bash
# README's picture, docs/img/viewer.png: the page `clothlab view` writes for the default run
# (configs/default.yaml), in headless Chromium (software WebGL, as tests/viewer/browser_test.py
# drives it), paused at T seconds.
# Usage: tools/viewer-picture.sh [BUILD_DIR] [T]   (default build, 1.0: the flag broadside)
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
t=${2:-1.0}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
clothlab=$(realpath "$build/bin/clothlab")
config=$(realpath configs/default.yaml)
# Run from the work folder, so the page names the run by the default config's own frames folder.
(cd "$work" && "$clothlab" --config "$config" --quiet &&
  "$clothlab" view results/default-frames --out view >/dev/null)
chromium --headless --no-sandbox --disable-gpu --disable-quic --no-first-run \
  --disable-background-networking --disable-component-update --disable-sync \
  --user-data-dir="$work/profile" --use-angle=swiftshader --enable-unsafe-swiftshader \
  --window-size=1000,600 --virtual-time-budget=5000 --screenshot="$work/viewer.png" \
  "file://$work/view/index.html?t=$t&paused=1" 2>/dev/null
cp "$work/viewer.png" docs/img/viewer.png
echo "wrote docs/img/viewer.png (the default run at t = $t s)"
