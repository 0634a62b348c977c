#!/bin/bash
# The scaling table of docs/results.md ("Choose": the cotton flag at 60 Hz, 50² to 300²): clothlab
# --choose on the cotton flag at 60 Hz for each side given (default 50 100 200 300), one after
# the other, each with its preset configs/choose-cotton-flag-<side>.yaml and implicit_euler's
# multigrid preconditioner. Each run's table goes to results/choose-cotton-flag-<side>.txt, with
# the date, commit and load average (uptime) before and after it: on a shared machine the
# ratios within one run are what count. Then:
#   tools/plot.py scaling results/choose-cotton-flag-{50,100,200,300}-ranked.json --out docs/img
# Usage: tools/choose-scaling.sh [side ...] [-- clothlab option ...]
#   (from the repository root, after the build); the options after -- go to every run, e.g.
#   -- --set choose.duration=0.25
# CHOOSE_TAG=name writes results/choose-cotton-flag-<side>-<name>.* instead (another search
# of the same scene, e.g. one integrator alone: -- --set 'choose.integrators=[implicit_euler]').
set -euo pipefail
sides=()
while [ $# -gt 0 ] && [ "$1" != "--" ]; do
  sides+=("$1")
  shift
done
[ $# -eq 0 ] || shift
[ ${#sides[@]} -gt 0 ] || sides=(50 100 200 300)
mkdir -p results
for side in "${sides[@]}"; do
  config="configs/choose-cotton-flag-$side.yaml"
  [ -f "$config" ] || { echo "choose-scaling.sh: $config: no preset for side $side" >&2; exit 1; }
  output="results/choose-cotton-flag-$side${CHOOSE_TAG:+-$CHOOSE_TAG}"
  log="$output.txt"
  {
    echo "commit $(git rev-parse --short HEAD)$(git diff --quiet HEAD || echo ' (modified)')"
    echo "options: ${*:-none}"
    echo "before: $(date -u '+%F %T UTC') $(uptime)"
  } >"$log"
  start=$(date +%s)
  build/bin/clothlab --choose --config "$config" --set plugin_params.implicit_euler.multigrid=1 \
    --set choose.output="$output" "$@" >>"$log"
  echo "after: $(date -u '+%F %T UTC') $(uptime); wall $(($(date +%s) - start)) s" >>"$log"
  cat "$log"
done
