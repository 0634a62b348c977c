#!/usr/bin/env bash
# A/B of two plugin folders, or of two whole builds, on the same microbenchmarks: runs
# clothlab_microbench with CLOTHLAB_PLUGIN_PATH=A, then =B, ROUNDS times in turn, and prints per
# benchmark the median real time of each side and the median of the per-round ratios B/A.
# Alternating rounds (A then B, then B then A) cancel most of a shared machine's drift, which
# two runs minutes apart do not. A side that is a build folder (with bin/clothlab_microbench)
# runs that build's microbenchmarks with its own plugins: two commits of the core compared in
# one run. After each turn the FMA probe (clothlab_fma_peak, two threads) reads the threads'
# mean FMA rate; a round with a probe under 3/4 of the run's best ran on physical cores that
# the host shared with other busy hardware threads (a guest sees no steal for it), and the
# medians are printed over all rounds and over the rounds whose two probes read full rate.
# Usage: tools/ab-plugins.sh ROUNDS FOLDER_A FOLDER_B FILTER [MIN_TIME]
#   e.g. tools/ab-plugins.sh 6 /tmp/before build/lib/clothlab/plugins 'xpbd_substep/300/'
#        tools/ab-plugins.sh 5 /tmp/old/build build 'fast_step/verlet/300/'
# Environment: MICROBENCH (build/bin/clothlab_microbench), for plugin folders; FMA_PEAK
# (build/bin/clothlab_fma_peak where built; empty: no probe). CLOTHLAB_SIMD passes through to both sides.
set -euo pipefail
cd "$(dirname "$0")/.."
if [[ $# -lt 4 || $# -gt 5 ]]; then
  echo "usage: tools/ab-plugins.sh ROUNDS FOLDER_A FOLDER_B FILTER [MIN_TIME]" >&2
  exit 1
fi
rounds=$1 folder_a=$2 folder_b=$3 filter=$4 min_time=${5:-0.2}
microbench=${MICROBENCH:-build/bin/clothlab_microbench}
if [[ -v FMA_PEAK ]]; then
  fma_peak=$FMA_PEAK
  [[ -z $fma_peak || -x $fma_peak ]] ||
    { echo "ab-plugins: no FMA probe $fma_peak (build the clothlab_fma_peak target, or FMA_PEAK= for none)" >&2; exit 1; }
else
  fma_peak=build/bin/clothlab_fma_peak
  [[ -x $fma_peak ]] || { echo "ab-plugins: no $fma_peak: rounds run without the FMA probe" >&2; fma_peak=; }
fi
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
  order="A B"
  ((round % 2 == 0)) && order="B A"
  for side in $order; do
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
    if [[ -n $fma_peak ]]; then
      probe=$("$fma_peak" --benchmark_filter=threads:2 --benchmark_min_time=0.1 2>/dev/null |
        grep -o 'gflops_per_thread=[0-9.]*' | cut -d= -f2) ||
        { echo "ab-plugins: the FMA probe $fma_peak failed" >&2; exit 1; }
      echo "probe $round $side $probe" >>"$results"
    fi
  done
done
python3 - "$results" <<'EOF'
import collections, statistics, sys
times = collections.defaultdict(dict)
units = {}
probes = collections.defaultdict(dict)
for line in open(sys.argv[1]):
    fields = line.split()
    if fields[0] == "probe":
        probes[fields[1]][fields[2]] = float(fields[3])
        continue
    round_, side, name, time, unit = fields
    times[(name, round_)][side] = float(time)
    units[name] = unit
best = max((v for p in probes.values() for v in p.values()), default=0.0)
shared = {r for r, p in probes.items() if min(p.values()) < 0.75 * best}
if probes:
    print("FMA probe, Gflop/s per thread after each turn: " + "; ".join(
        f"round {r} A {probes[r].get('A', 0):.0f} B {probes[r].get('B', 0):.0f}"
        + (" (shared)" if r in shared else "") for r in sorted(probes, key=int)))


def summary(rounds_kept, label):
    ratios, a, b = (collections.defaultdict(list) for _ in range(3))
    for (name, round_), sides in times.items():
        if "A" in sides and "B" in sides and round_ in rounds_kept:
            a[name].append(sides["A"])
            b[name].append(sides["B"])
            ratios[name].append(sides["B"] / sides["A"])
    print(label)
    for name in sorted(ratios):
        r = ratios[name]
        print(f"  {name}: A {statistics.median(a[name]):.0f} {units[name]}, "
              f"B {statistics.median(b[name]):.0f} {units[name]}, B/A median {statistics.median(r):.3f} "
              f"(rounds {len(r)}: {', '.join(f'{x:.3f}' for x in r)})")


all_rounds = {round_ for (_, round_) in times}
if not any("A" in s and "B" in s for s in times.values()):
    sys.exit("ab-plugins: no benchmark matched the filter on both sides")
summary(all_rounds, "all rounds:")
if shared and all_rounds - shared:
    summary(all_rounds - shared, "rounds whose probes read full rate:")
EOF
