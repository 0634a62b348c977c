#!/usr/bin/env bash
# Per-case overhead of `clothlab --config sweep.yaml` end to end on trivial cases (one step of
# a 2 x 2 sheet): config checks, the case worker (plugin loading and the step per case), the
# results store, and the CSV/JSON exports at the end. Runs each case count REPEATS times
# (default 3) and prints the median wall time and ms per case, the range of ms per case, and
# the median CPU time (user + system, the program and its children) per case: on a shared
# machine the wall time also counts the waits for a core.
# Usage: tools/sweep_overhead.sh [N...]   (default 250 2000 10000; BUILD_DIR default build)
set -euo pipefail
cd "$(dirname "$0")/.."
clothlab=${BUILD_DIR:-build}/bin/clothlab
repeats=${REPEATS:-3}
sizes=("$@")
((${#sizes[@]})) || sizes=(250 2000 10000)
for n in "${sizes[@]}"; do
  [[ "$n" =~ ^[1-9][0-9]*$ ]] || { echo "sweep_overhead.sh: case count '$n': allowed: a whole number >= 1" >&2; exit 1; }
done
[[ "$repeats" =~ ^[1-9][0-9]*$ ]] || { echo "sweep_overhead.sh: REPEATS='$repeats': allowed: a whole number >= 1" >&2; exit 1; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
echo "cases  runs  median_wall_s  median_ms_per_case  min_ms  max_ms  median_cpu_ms_per_case"
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
  timings=()
  TIMEFORMAT='%R %U %S'
  for ((run = 0; run < repeats; ++run)); do
    # bash's time: wall, then user and system CPU of the program and the children it waited for.
    timing=$({ time "$clothlab" --config "$work/overhead-$n.yaml" --out "$work" > /dev/null; } 2>&1)
    rows=$(($(wc -l < "$work/overhead-$n.csv") - 1))
    [ "$rows" -eq "$n" ] || { echo "expected $n rows, got $rows" >&2; exit 1; }
    timings+=("$(awk '{ printf "%.3f %.3f", $1, $2 + $3 }' <<< "$timing")")
  done
  median() { sort -g | awk '{ v[NR] = $1 } END { print NR % 2 ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2 }'; }
  walls=$(printf '%s\n' "${timings[@]}" | cut -d' ' -f1)
  wall=$(median <<< "$walls")
  cpu=$(printf '%s\n' "${timings[@]}" | cut -d' ' -f2 | median)
  least=$(sort -g <<< "$walls" | head -1)
  most=$(sort -g <<< "$walls" | tail -1)
  awk -v n="$n" -v runs="$repeats" -v wall="$wall" -v least="$least" -v most="$most" -v cpu="$cpu" 'BEGIN {
    printf "%5d  %4d  %13.2f  %18.3f  %6.3f  %6.3f  %22.3f\n", n, runs, wall, wall * 1000 / n,
           least * 1000 / n, most * 1000 / n, cpu * 1000 / n
  }'
done
