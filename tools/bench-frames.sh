#!/usr/bin/env bash
# Issue-10 tables: real cloth in a real frame budget, for every integrator on the plugin path.
# For each scenario x mesh x frame rate, `clothlab --choose` on configs/bench-300.yaml (cotton,
# Earth gravity, float32, all threads) finds every integrator's cheapest setting that stays
# stable over 1 s, keeps the warp/weft stretch <= STRETCH_LIMIT and the position error <=
# ERROR_TOLERANCE of the diagonal at T = 0.25 s (judged on the mesh itself; on the flag from
# 200 x 200 float32's own floor is about 1 % or more and --choose refuses a bar below it, so the
# default is 2 %: configs/choose-cotton-flag-200.yaml), and reports ms per frame and the
# real-time factor. The reference step is the same at every frame rate (512 substeps at 60 Hz,
# 1024 at 30 Hz, up to 100 x 100; twice that above: at 200 x 200 rk4 at 512 diverges), so one
# float64 reference per mesh serves every table (cached in $RESULTS_DIR/references). Then,
# per table, tools/plot.py draws the probes' cost per frame against their error, and, where the
# mesh is at most ENERGY_MESH, each passing setting is run once more with --energy-out for the
# energy-over-time plot.
# Usage: tools/bench-frames.sh
# Environment: BUILD_DIR (build), RESULTS_DIR (results/bench-frames), SCENARIOS ("flag"),
#              MESHES ("50 100 200"), FRAME_RATES ("60 30"), INTEGRATORS (empty: every one on
#              the path, in the 200 x 200 preset's order), STRETCH_LIMIT (1.10),
#              ERROR_TOLERANCE (0.02), STOP_FACTOR (3),
#              ENERGY_MESH (50), PLOTS (1: draw the plots; needs python3-matplotlib).
# Results: $RESULTS_DIR/choose-<scenario>-<mesh>-<rate>Hz{,-ranked}.{csv,json}, the printed
#          table (.txt), plots/, energy-*.csv, and summary.md (machine, date, load, wall times
#          and every table, for lab/real-cloth.md).
set -euo pipefail
cd "$(dirname "$0")/.."
build_dir=${BUILD_DIR:-build}
results=${RESULTS_DIR:-results/bench-frames}
integrators=${INTEGRATORS:-verlet euler xpbd_tethers xpbd vbd rk4 midpoint projective_dynamics implicit_euler bdf2}
bin="$build_dir/bin/clothlab"
# OMP_WAIT_POLICY is passed through as set: on a machine shared with other jobs set it to
# passive (threads spinning at their barriers lose their core for whole time slices); on an idle
# machine leave it unset, since sleeping at every barrier slows each step there
# (lab/real-cloth.md, "OpenMP on a shared machine").
mkdir -p "$results"
summary="$results/summary.md"
{
  echo "Machine: $(lscpu | sed -n 's/^Model name: *//p' | head -1), $(nproc) cores;" \
    "$(date -u '+%Y-%m-%d %H:%M UTC'); load average at the start: $(cut -d' ' -f1-3 /proc/loadavg)"
  echo "Commit: $(git rev-parse --short HEAD)$(git diff --quiet || echo ' (with local changes)')"
  echo "OMP_WAIT_POLICY=${OMP_WAIT_POLICY:-(unset)}"
} >"$summary"

for rate in ${FRAME_RATES:-60 30}; do
  for mesh in ${MESHES:-50 100 200}; do
    for scenario in ${SCENARIOS:-flag}; do
      reference_substeps=$(((mesh > 100 ? 1024 : 512) * 60 / rate))
      name="choose-$scenario-$mesh-${rate}Hz"
      started=$(date +%s)
      "$bin" --choose --config configs/bench-300.yaml --scenario "$scenario" \
        --set scenario.rows="$mesh" --set scenario.cols="$mesh" --frame-rate "$rate" \
        --set choose.reference_substeps="$reference_substeps" \
        --set choose.stretch_limit="${STRETCH_LIMIT:-1.10}" \
        --set choose.error_tolerance="${ERROR_TOLERANCE:-0.02}" \
        --set choose.stop_factor="${STOP_FACTOR:-3}" \
        --set "choose.integrators=[${integrators// /, }]" \
        --set choose.reference_cache="$results/references" \
        --set choose.output="$results/$name" | tee "$results/$name.txt"
      wall=$(($(date +%s) - started))
      {
        echo
        echo "### $scenario ${mesh}x$mesh, $rate Hz ($((wall / 60)) min $((wall % 60)) s wall," \
          "load average after: $(cut -d' ' -f1-3 /proc/loadavg))"
        echo
        echo '```'
        cat "$results/$name.txt"
        echo '```'
      } >>"$summary"
      [[ ${PLOTS:-1} == 1 ]] || continue
      /usr/bin/python3 tools/plot.py choose "$results/$name.json" --out "$results/plots/$name" \
        --cloth "cotton $scenario ${mesh}x$mesh, $rate Hz" >/dev/null
      ((mesh <= ${ENERGY_MESH:-50})) || continue
      # Each passing setting once more, with its energy trace.
      traces=()
      while IFS=, read -r integrator substeps iterations parameter; do
        extra=()
        [[ -n $iterations ]] && extra+=(--set integrator."$parameter"="$iterations")
        trace="$results/energy-$name-$integrator.csv"
        "$bin" --config configs/bench-300.yaml --scenario "$scenario" --integrator "$integrator" \
          --set scenario.rows="$mesh" --set scenario.cols="$mesh" --frame-rate "$rate" \
          --substeps "$substeps" --duration 1 "${extra[@]}" --energy-out "$trace" --quiet
        traces+=("$trace")
      done < <(python3 -c '
import csv, sys
for row in csv.DictReader(open(sys.argv[1])):
    if row["rank"]:
        print(row["integrator"], row["substeps"], row["iterations"],
              row["iterations_parameter"], sep=",")
' "$results/$name-ranked.csv")
      ((${#traces[@]} > 0)) && /usr/bin/python3 tools/plot.py energy "${traces[@]}" \
        --out "$results/plots/$name" --cloth "cotton $scenario ${mesh}x$mesh, $rate Hz" >/dev/null
    done
  done
done
echo "summary: $summary"
