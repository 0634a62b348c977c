#!/usr/bin/env bash
# Fuzzes the clothlab program with mutated configs, sweep files and command lines
# (tools/fuzz.py; corpus in tests/fuzz/corpus). Usage: tools/fuzz.sh [--small] [CLOTHLAB]
#   --small   200 inputs (CI); otherwise 2000 (the documented larger run)
# Prints the counts of crashes, hangs, partial outputs and bad errors; exit 1 if any.
set -euo pipefail
cd "$(dirname "$0")/.."
count=2000
if [[ "${1:-}" == "--small" ]]; then
  count=200
  shift
fi
executable="${1:-build/bin/clothlab}"
exec python3 tools/fuzz.py "$executable" --count "$count" --seed "${FUZZ_SEED:-12}" \
  --failures "${FUZZ_FAILURES:-build/fuzz-failures.txt}"
