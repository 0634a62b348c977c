#!/usr/bin/env bash
# Stability sweeps: builds ClothLab (tools/build.sh), then
#  1. configs/stability.yaml: largest stable dt per integrator x scenario x mesh (bisection on
#     real runs with the objective verdict) beside the predicted dt_max;
#  2. configs/seed-2016-matrix.yaml: the seed's 240-run test matrix, one verdict per case
#     (skip it with SKIP_MATRIX=1);
# and plots both. Results and pictures go to results/stability/ (or the folder given).
# Kept short by 0.3 s probes and a 10 % tolerance for the searches, 2 s per matrix case (see
# the configs' comments; run times: lab/performance.md, "Tool run times").
# Extra arguments after the folder go to clothlab, e.g. --resume. BUILD_DIR=<folder> uses an
# existing Release build there instead of building ./build.
set -euo pipefail
cd "$(dirname "$0")/.."
out="${1:-results/stability}"
shift || true
if [ -n "${BUILD_DIR:-}" ]; then
  clothlab="$BUILD_DIR/bin/clothlab"
else
  bash tools/build.sh >/dev/null
  clothlab=./build/bin/clothlab
fi
mkdir -p "$out"
# The scenarios' default springs are per spring, not per material: the finer the mesh, the
# softer the cloth, and hanging from two corners its corner springs sit at 3.6x rest (50x50) and
# far more (200x200) in equilibrium. The stretch check would then call every dt unstable, so the
# search judges by the non-finite and energy checks (stretch limit 1000x: only blow-ups).
"$clothlab" --config configs/stability.yaml --out "$out" --set stability.max_stretch=1000 "$@"
# Large steps (configs/stability-large-dt.yaml): all seven integrators on the default 50x50
# cloth and on one with every ks and kd ten times larger, searched up to dt = 50 ms.
# The stiff cloth: the scenarios' default springs (ks 20/10/1 N/m, kd = 7e-4 ks) times 10.
stiff=(--set scenario.structural.ks=200 --set scenario.structural.kd=0.14
       --set scenario.shear.ks=100 --set scenario.shear.kd=0.07
       --set scenario.flexion.ks=10 --set scenario.flexion.kd=0.007)
"$clothlab" --config configs/stability-large-dt.yaml --out "$out" --set stability.max_stretch=1000 "$@"
"$clothlab" --config configs/stability-large-dt.yaml --out "$out/stiff" \
  --set stability.max_stretch=1000 "${stiff[@]}" "$@"
matrix=()
if [ "${SKIP_MATRIX:-0}" != 1 ]; then
  "$clothlab" --config configs/seed-2016-matrix.yaml --out "$out" "$@"
  matrix=(--matrix "$out/seed-2016-matrix.json")
fi
/usr/bin/python3 tools/plot.py stability "$out/stability.json" "${matrix[@]}" --out "$out" \
  --cloth "default cloth" --matrix-cloth "seed §5.1 cloth (100 kg, ks 20, kd 7.5)"
# Large steps: default and 10x stiffer cloth.
for results in "$out/stability-large-dt.json" "$out/stiff/stability-large-dt.json"; do
  echo "== $results"
  /usr/bin/python3 - "$results" <<'PY'
import json, sys
for row in json.load(open(sys.argv[1]))["rows"]:
    print(f'{row["integrator"]:20} {row["scenario"]:6} measured {row["dt_max"]:.4g} s ({row["outcome"]}, {row["check"] or "-"})')
PY
done
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
if [ "${SKIP_MATRIX:-0}" != 1 ]; then
  seed="${SEED_TEXT:-/work/shared/seed/001_e1c50b133d58c230.txt}"
  [ -f "$seed" ] && /usr/bin/python3 - "$seed" "$out/seed-2016-matrix.json" <<'PY'
import json, re, sys
# Seed appendix C tables (C.2 ... C.16) against the objective verdicts of the matrix sweep.
seed_text = open(sys.argv[1]).read().splitlines()
tables = {"C.2": ("euler", "sheet"), "C.4": ("euler", "flag"), "C.6": ("verlet", "sheet"),
          "C.8": ("verlet", "flag"), "C.10": ("midpoint", "sheet"), "C.12": ("midpoint", "flag"),
          "C.14": ("rk4", "sheet"), "C.16": ("rk4", "flag")}
meshes = [50, 100, 150, 200, 250, 300]; dts = [1, 5, 10, 15, 20]
seed = {}
for i, line in enumerate(seed_text):
    m = re.match(r"Table (C\.\d+): Stability results", line)
    if not m or m.group(1) not in tables: continue
    cells = [l.split("\t")[2].strip() for l in seed_text[max(0, i - 80):i]
             if re.match(r".*\t\d+\t(Stable|Unstable)\s*$", l)][-30:]
    for k, verdict in enumerate(cells):
        seed[tables[m.group(1)] + (meshes[k // 5], dts[k % 5])] = verdict == "Stable"
rows = json.load(open(sys.argv[2]))["rows"]
ours = {}
for r in rows:
    mesh = int(r["mesh"].split("x")[0]); dt = round(float(r["dt"]) * 1000)
    ours[(r["integrator"], r["scenario"], mesh, dt)] = (r["status"], r.get("check") or "", r.get("fail_step"))
agree = disagree = 0
for (integ, scen) in tables.values():
    print(f"{integ} {scen}: mesh \\ dt(ms) " + " ".join(f"{d:>6}" for d in dts))
    for mesh in meshes:
        cells = []
        for dt in dts:
            s = seed.get((integ, scen, mesh, dt)); o = ours.get((integ, scen, mesh, dt))
            if s is None or o is None: cells.append("  ?   "); continue
            ok = (o[0] == "stable") == s
            agree += ok; disagree += not ok
            cells.append(("S" if s else "U") + "/" + (o[0][0].upper() + (o[1][:1] if o[1] else "")) + ("  " if ok else " !"))
        print(f"   {mesh:>4}^2 " + " ".join(f"{c:>6}" for c in cells))
print(f"agree {agree}, disagree {disagree}  (cell: seed/ours; ours S stable, U unstable + check n/s/e, F failed; ! = differs)")
PY
fi
