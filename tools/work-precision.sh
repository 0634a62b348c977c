#!/usr/bin/env bash
# Work-precision sweep (configs/work-precision.yaml): builds ClothLab (tools/build.sh), runs the
# sweep -- error at T = 0.5 s against a float64 RK4 reference, dt ladders, fitted orders --
# and plots it. Results and pictures go to results/work-precision/ (or the folder given).
# Extra arguments after the folder go to clothlab, e.g. --resume.
set -euo pipefail
cd "$(dirname "$0")/.."
out="${1:-results/work-precision}"
shift || true
bash tools/build.sh >/dev/null
mkdir -p "$out"
./build/bin/clothlab --config configs/work-precision.yaml --out "$out" "$@"
/usr/bin/python3 tools/plot.py work-precision "$out/work-precision.json" --out "$out"
# The measured orders, one line per integrator x scenario x precision.
/usr/bin/python3 - "$out/work-precision.json" <<'PY'
import json, sys
for row in json.load(open(sys.argv[1]))["rows"]:
    if row.get("kind") == "fit":
        print(f'{row["integrator"]:9} {row["scenario"]:6} {row["precision"]:8} order '
              f'{row["order"] if row["order"] is not None else "-":>8.6} over dt '
              f'{row["fit_dt_min"]}..{row["fit_dt_max"]} s ({row["fit_points"]} points) {row["note"]}')
PY
