#!/usr/bin/env bash
# Issue-4 benchmark table from one run: builds Release with -march=native, then measures
#   - each integrator x scenario at 300 x 300, dt 1 ms, float32 (configs/bench-300-soft.yaml):
#     ms/step (median of REPS runs' median step times), real-time factor = dt / that,
#     internal-force throughput (springs/s, median over runs);
#   - the euler flag step of the fast core vs the in-run baseline (seed-style reference
#     forces + the same Euler update, one thread), alternating in one process;
#   - euler flag cost vs mesh size (50^2 ... 1000^2) to show linear scaling;
#   - the cost of --frames (bench/frames_bench.py): euler and rk4 flag at 300 x 300 (the soft
#     cloth, dt 1 ms: cotton diverges with explicit methods at that step) without
#     frames and with frames at 60 per simulated second (.vtp + .pvd) for FRAME_STEPS and
#     2 x FRAME_STEPS steps, interleaved, FRAME_REPS times per FRAME_THREADS thread count:
#     loop ms/step, paired slowdown, writer ms/frame, peak RSS for N and 2N frames.
# Usage: tools/bench.sh [--micro | --frames]   (--micro also runs the Google Benchmark
#        suite; --frames runs only the frames comparison)
# Environment: BUILD_DIR (build-bench), RESULTS_DIR ($BUILD_DIR/bench-results), REPS (5), STEPS (200),
#              THREADS (0 = all), FRAME_STEPS (1000), FRAME_REPS (7), FRAME_THREADS ("1 0").
# Results: $RESULTS_DIR/table.md, summary.json, runs.csv, speedup.json, frames.md, frames.json,
#          raw JSON per run.
set -euo pipefail
cd "$(dirname "$0")/.."
build_dir=${BUILD_DIR:-build-bench}
results=${RESULTS_DIR:-$build_dir/bench-results}
reps=${REPS:-5}
steps=${STEPS:-200}
threads=${THREADS:-0}
frame_steps=${FRAME_STEPS:-1000}
frame_reps=${FRAME_REPS:-7}
frame_threads=${FRAME_THREADS:-1 0}
micro=0 frames_only=0
[[ ${1:-} == --micro ]] && micro=1
[[ ${1:-} == --frames ]] && frames_only=1

cmake -S . -B "$build_dir" -DCMAKE_BUILD_TYPE=Release -DCLOTHLAB_NATIVE=ON >/dev/null
extra_targets=(clothlab_speedup)
[[ $micro == 1 ]] && extra_targets+=(clothlab_microbench)
[[ $frames_only == 1 ]] && extra_targets=()
cmake --build "$build_dir" -j "$(nproc)" --target clothlab euler midpoint rk4 verlet sheet flag \
  "${extra_targets[@]}" >/dev/null
mkdir -p "$results/runs"
bin="$build_dir/bin"
machine="$(lscpu | sed -n 's/^Model name: *//p' | head -1)"

frames_comparison() {
  python3 bench/frames_bench.py --bin "$bin" --config configs/bench-300-soft.yaml --results "$results" \
    --reps "$frame_reps" --steps "$frame_steps" --threads $frame_threads
}
if [[ $frames_only == 1 ]]; then
  frames_comparison
  exit 0
fi

for rep in $(seq 1 "$reps"); do
  for scenario in sheet flag; do
    for integrator in euler verlet midpoint rk4; do
      "$bin/clothlab" --config configs/bench-300-soft.yaml --integrator "$integrator" \
        --scenario "$scenario" --steps "$steps" --threads "$threads" --quiet \
        --json "$results/runs/$scenario-$integrator-$rep.json"
    done
  done
done

"$bin/clothlab_speedup" configs/bench-300-soft.yaml "$reps" "$steps" >"$results/speedup.json"

# Same material and spacing as bench-300 (2 cm, 0.6 kg/m^2) at every size.
for side in 50 100 200 300 500 1000; do
  size=$(python3 -c "print(6.0 * $side / 300)")
  mass=$(python3 -c "print(0.6 * (6.0 * $side / 300) ** 2)")
  "$bin/clothlab" --config configs/bench-300-soft.yaml --integrator euler --scenario flag \
    --set scenario.rows="$side" --set scenario.cols="$side" --set scenario.width="$size" \
    --set scenario.height="$size" --set scenario.mass="$mass" --steps "$steps" \
    --threads "$threads" --quiet --json "$results/runs/scaling-$side.json"
done

python3 bench/bench_table.py "$results" "$machine"
frames_comparison
[[ $micro == 1 ]] && "$bin/clothlab_microbench" --benchmark_out="$results/microbench.json" \
  --benchmark_out_format=json --benchmark_counters_tabular=true --benchmark_repetitions="$reps" \
  --benchmark_report_aggregates_only=true
exit 0
