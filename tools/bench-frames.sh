#!/usr/bin/env bash
# Issue-10 benchmark: real cloth in a real frame budget. For each scenario x mesh x frame rate,
# `clothlab --choose` on configs/bench-300.yaml (cotton, Earth gravity, float32, all threads)
# finds every integrator's cheapest setting that stays stable over 1 s, keeps the warp/weft
# stretch <= 5 % and the position error <= 1 % of the diagonal (measured at 100 x 100, or at
# the mesh itself when it is smaller), and reports ms per frame and the real-time factor.
# Usage: tools/bench-frames.sh
# Environment: BUILD_DIR (build), RESULTS_DIR (results/bench-frames), SCENARIOS ("sheet flag"),
#              MESHES ("300"), FRAME_RATES ("60"), INTEGRATORS (empty: every one on the path).
# Results: $RESULTS_DIR/choose-<scenario>-<mesh>-<rate>Hz{,-ranked}.{csv,json} and .txt tables.
set -euo pipefail
cd "$(dirname "$0")/.."
build_dir=${BUILD_DIR:-build}
results=${RESULTS_DIR:-results/bench-frames}
mkdir -p "$results"
for rate in ${FRAME_RATES:-60}; do
  for mesh in ${MESHES:-300}; do
    for scenario in ${SCENARIOS:-sheet flag}; do
      error_mesh=$((mesh < 100 ? mesh : 100))
      name="choose-$scenario-$mesh-${rate}Hz"
      extra=()
      [[ -n ${INTEGRATORS:-} ]] && extra+=(--set "choose.integrators=[${INTEGRATORS// /, }]")
      "$build_dir/bin/clothlab" --choose --config configs/bench-300.yaml --scenario "$scenario" \
        --set scenario.rows="$mesh" --set scenario.cols="$mesh" --frame-rate "$rate" \
        --set choose.error_mesh="${error_mesh}x${error_mesh}" \
        --set choose.output="$results/$name" "${extra[@]}" | tee "$results/$name.txt"
    done
  done
done
