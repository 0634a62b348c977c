#!/usr/bin/env bash
# Stability sweeps: builds ClothLab (tools/build.sh), then
#  1. configs/stability.yaml: largest stable dt per integrator x scenario x mesh (bisection on
#     real runs with the objective verdict) beside the predicted dt_max;
#  2. configs/seed-2016-matrix.yaml: the seed's 240-run test matrix, one verdict per case
#     (skip it with SKIP_MATRIX=1);
# and plots both. Results and pictures go to results/stability/ (or the folder given).
# Extra arguments after the folder go to clothlab, e.g. --resume.
set -euo pipefail
cd "$(dirname "$0")/.."
out="${1:-results/stability}"
shift || true
bash tools/build.sh >/dev/null
mkdir -p "$out"
# The scenarios' default springs are per spring, not per material: the finer the mesh, the
# softer the cloth, and hanging from two corners its corner springs sit at 3.6x rest (50x50) and
# far more (200x200) in equilibrium. The stretch check would then call every dt unstable, so the
# search judges by the non-finite and energy checks (stretch limit 1000x: only blow-ups).
./build/bin/clothlab --config configs/stability.yaml --out "$out" --set stability.max_stretch=1000 "$@"
matrix=()
if [ "${SKIP_MATRIX:-0}" != 1 ]; then
  ./build/bin/clothlab --config configs/seed-2016-matrix.yaml --out "$out" "$@"
  matrix=(--matrix "$out/seed-2016-matrix.json")
fi
/usr/bin/python3 tools/plot.py stability "$out/stability.json" "${matrix[@]}" --out "$out"
# Predicted against measured dt_max, one line per integrator x scenario x mesh.
/usr/bin/python3 - "$out/stability.json" <<'PY'
import json, sys
def g(v):
    return f"{v:.4g}" if isinstance(v, (int, float)) else "-"
for row in json.load(open(sys.argv[1]))["rows"]:
    print(f'{row["integrator"]:9} {row["scenario"]:6} {row["mesh"]:8} measured {g(row["dt_max"]):>10} s'
          f'  predicted {g(row["predicted_dt_max"]):>10} s  ratio {g(row["measured_over_predicted"])}'
          f'  ({row["outcome"]}, {row["check"] or "-"})')
PY
