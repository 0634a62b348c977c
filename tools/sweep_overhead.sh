#!/usr/bin/env bash
# Per-case overhead of `clothlab --config sweep.yaml` end to end on trivial cases (one step of
# a 2 x 2 sheet): config checks, the child process per case (fork, plugin loading, the step),
# the results store, and the CSV/JSON exports at the end. Prints ms per case for each size.
# Usage: tools/sweep_overhead.sh [N...]   (default 250 2000 10000; BUILD_DIR default build)
set -euo pipefail
cd "$(dirname "$0")/.."
clothlab=${BUILD_DIR:-build}/bin/clothlab
sizes=("$@")
((${#sizes[@]})) || sizes=(250 2000 10000)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
echo "cases  wall_s  ms_per_case"
for n in "${sizes[@]}"; do
  # n distinct time steps of 1 us ... n us: n cases that each run one step.
  dts=$(seq -s ', ' 1 "$n" | sed 's/\([0-9][0-9]*\)/\1e-6/g')
  cat > "$work/overhead-$n.yaml" << YAML
steps: 1
threads: 1
scenario: {rows: 2, cols: 2}
sweep:
  name: overhead-$n
  mode: run
  matrix:
    integrator: [euler]
    scenario: [sheet]
    dt: [$dts]
YAML
  start=$(date +%s.%N)
  "$clothlab" --config "$work/overhead-$n.yaml" --out "$work" > /dev/null
  end=$(date +%s.%N)
  rows=$(($(wc -l < "$work/overhead-$n.csv") - 1))
  [ "$rows" -eq "$n" ] || { echo "expected $n rows, got $rows" >&2; exit 1; }
  awk -v n="$n" -v s="$start" -v e="$end" 'BEGIN { printf "%5d  %6.2f  %11.2f\n", n, e - s, (e - s) * 1000 / n }'
done
