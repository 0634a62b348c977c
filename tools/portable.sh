#!/usr/bin/env bash
# Builds ClothLab without -march=native (CLOTHLAB_NATIVE=OFF, the portable build packagers ship)
# into ./build-portable and runs the test suite there. Extra arguments go to ctest.
set -euo pipefail
cd "$(dirname "$0")/.."
build="build-portable"
cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Release -DCLOTHLAB_NATIVE=OFF \
  -DCLOTHLAB_BUILD_BENCH=OFF >/dev/null
cmake --build "$build" -j "$(nproc)"
ctest --test-dir "$build" --output-on-failure --timeout 300 -j "$(nproc)" "$@"
