#!/usr/bin/env bash
# Builds ClothLab without -march=native (CLOTHLAB_NATIVE=OFF, the portable build packagers ship)
# into ./build-portable and runs there the tests labelled `kernels` (the core's and the plugins'
# kernels: the code -march changes; tests/CMakeLists.txt); only their executables are built.
# Extra arguments go to ctest.
set -euo pipefail
cd "$(dirname "$0")/.."
build="build-portable"
cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Release -DCLOTHLAB_NATIVE=OFF \
  -DCLOTHLAB_BUILD_BENCH=OFF >/dev/null
cmake --build "$build" -j "$(nproc)" --target tests_kernels
ctest --test-dir "$build" --output-on-failure --timeout 300 -j "$(nproc)" -L kernels "$@"
