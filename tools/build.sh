#!/usr/bin/env bash
# Installs dependencies, configures and builds ClothLab into ./build (Release).
set -euo pipefail
cd "$(dirname "$0")/.."
bash tools/install-deps.sh
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release "$@"
cmake --build build -j "$(nproc)"
