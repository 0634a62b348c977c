#!/usr/bin/env bash
# Sets up, builds and runs the whole test suite (the command CI runs).
set -euo pipefail
cd "$(dirname "$0")/.."
bash tools/build.sh test
# A test without a TIMEOUT of its own is stopped after 300 s: a hang fails, never stalls CI.
ctest --test-dir build --output-on-failure --timeout 300 -j "$(nproc)"
# The plugin author's round trip: install, build the example out of tree, conformance.
bash tools/ci-sdk.sh build
