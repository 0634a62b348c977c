#!/usr/bin/env bash
# Sets up, builds and runs the default scenario with the default configuration.
set -euo pipefail
cd "$(dirname "$0")/.."
bash tools/build.sh
./build/bin/clothlab --config configs/default.yaml "$@"
