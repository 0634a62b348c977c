#!/usr/bin/env bash
# A/B of two plugin folders, or of two whole builds, on the same microbenchmarks: runs
# clothlab_microbench with CLOTHLAB_PLUGIN_PATH=A, then =B, ROUNDS times in turn, and prints per
# benchmark the median real time of each side and the median of the per-round ratios B/A.
# Alternating rounds cancel most of a shared machine's drift, which two runs minutes apart do
# not. A side that is a build folder (with bin/clothlab_microbench) runs that build's
# microbenchmarks with its own plugins: two commits of the core compared in one run.
# Usage: tools/ab-plugins.sh ROUNDS FOLDER_A FOLDER_B FILTER [MIN_TIME]
#   e.g. tools/ab-plugins.sh 6 /tmp/before build/lib/clothlab/plugins 'xpbd_substep/300/'
#        tools/ab-plugins.sh 5 /tmp/old/build build 'fast_step/verlet/300/'
# Environment: MICROBENCH (build/bin/clothlab_microbench), for plugin folders.
set -euo pipefail
cd "$(dirname "$0")/.."
if [[ $# -lt 4 || $# -gt 5 ]]; then
  echo "usage: tools/ab-plugins.sh ROUNDS FOLDER_A FOLDER_B FILTER [MIN_TIME]" >&2
  exit 1
fi
rounds=$1 folder_a=$2 folder_b=$3 filter=$4 min_time=${5:-0.2}
microbench=${MICROBENCH:-build/bin/clothlab_microbench}
[[ $rounds =~ ^[1-9][0-9]*$ ]] || { echo "ab-plugins: ROUNDS must be a positive integer, got '$rounds'" >&2; exit 1; }
for folder in "$folder_a" "$folder_b"; do
  [[ -d $folder ]] || { echo "ab-plugins: no plugin folder $folder" >&2; exit 1; }
done
for folder in "$folder_a" "$folder_b"; do
  if [[ -x $folder/bin/clothlab_microbench ]]; then
    [[ -d $folder/lib/clothlab/plugins ]] ||
      { echo "ab-plugins: build folder $folder has no lib/clothlab/plugins" >&2; exit 1; }
  else
    [[ -x $microbench ]] ||
      { echo "ab-plugins: no $microbench (build first: bash tools/build.sh)" >&2; exit 1; }
  fi
done
results=$(mktemp)
run=$(mktemp)
trap 'rm -f "$results" "$run" "$run.err"' EXIT
for round in $(seq 1 "$rounds"); do
  for side in A B; do
    folder=$folder_a
    [[ $side == B ]] && folder=$folder_b
    bench=$microbench
    if [[ -x $folder/bin/clothlab_microbench ]]; then
      bench=$folder/bin/clothlab_microbench
      folder=$folder/lib/clothlab/plugins
    fi
    echo "ab-plugins: round $round/$rounds, $side ($bench, $folder)" >&2
    if ! CLOTHLAB_PLUGIN_PATH=$folder "$bench" --benchmark_filter="$filter" \
      --benchmark_min_time="$min_time" --benchmark_format=json >"$run" 2>"$run.err"; then
      echo "ab-plugins: $bench failed with $folder:" >&2
      cat "$run.err" >&2
      exit 1
    fi
    if [[ ! -s $run ]]; then
      echo "ab-plugins: $(cat "$run.err")" >&2
      exit 1
    fi
    python3 -c '
import json, sys
for b in json.load(open(sys.argv[1]))["benchmarks"]:
    if b.get("run_type", "iteration") == "iteration" and not b.get("error_occurred"):
        print(sys.argv[2], sys.argv[3], b["name"], b["real_time"], b["time_unit"])
' "$run" "$round" "$side" >>"$results"
  done
done
python3 - "$results" <<'EOF'
import collections, statistics, sys
times = collections.defaultdict(dict)
units = {}
for line in open(sys.argv[1]):
    round_, side, name, time, unit = line.split()
    times[(name, round_)][side] = float(time)
    units[name] = unit
ratios, a, b = (collections.defaultdict(list) for _ in range(3))
for (name, _), sides in times.items():
    if "A" in sides and "B" in sides:
        a[name].append(sides["A"])
        b[name].append(sides["B"])
        ratios[name].append(sides["B"] / sides["A"])
if not ratios:
    sys.exit("ab-plugins: no benchmark matched the filter on both sides")
for name in sorted(ratios):
    r = ratios[name]
    print(f"{name}: A {statistics.median(a[name]):.0f} {units[name]}, "
          f"B {statistics.median(b[name]):.0f} {units[name]}, B/A median {statistics.median(r):.3f} "
          f"(rounds {len(r)}: {', '.join(f'{x:.3f}' for x in r)})")
EOF
