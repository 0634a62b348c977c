#!/usr/bin/env bash
# Sets up what running needs (no test tools), builds and runs the default scenario with the
# default configuration (configs/default.yaml); extra arguments go to clothlab.
set -euo pipefail
cd "$(dirname "$0")/.."
bash tools/build.sh run
./build/bin/clothlab --config configs/default.yaml "$@"
