#!/usr/bin/env bash
# Installs dependencies, configures and builds ClothLab into ./build (Release).
#   build.sh run [cmake args]    the program and plugins only (what tools/run.sh needs)
#   build.sh test [cmake args]   also the test suite and the benchmarks
set -euo pipefail
cd "$(dirname "$0")/.."
profile="${1:-test}"
shift || true
bash tools/install-deps.sh "$profile"
parts=(-DCLOTHLAB_BUILD_TESTS=ON -DCLOTHLAB_BUILD_BENCH=ON)
# A first build for running leaves the tests out; a tree that has them keeps them.
if [ "$profile" = run ]; then
  parts=()
  [ -f build/CMakeCache.txt ] || parts=(-DCLOTHLAB_BUILD_TESTS=OFF -DCLOTHLAB_BUILD_BENCH=OFF)
fi
# A new tree is generated for Ninja (ninja-build), which compiles a target's files while the
# libraries it links are still being built, where Makefiles wait for them; a tree keeps the
# generator it was made with.
if command -v ninja >/dev/null; then export CMAKE_GENERATOR="${CMAKE_GENERATOR:-Ninja}"; fi
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release "${parts[@]}" "$@"
cmake --build build -j "$(nproc)"
