#!/usr/bin/env bash
# Sets up, builds and runs the whole test suite (the command CI runs).
set -euo pipefail
cd "$(dirname "$0")/.."
bash tools/build.sh
ctest --test-dir build --output-on-failure -j "$(nproc)"
# The plugin author's round trip: install, build the example out of tree, conformance.
bash tools/ci-sdk.sh build
