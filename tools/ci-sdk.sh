#!/usr/bin/env bash
# The SDK round trip a plugin author relies on (issue 3), against a configured build tree:
#  1. installs ClothLab to a temporary prefix;
#  2. configures and builds examples/third_party_integrator and examples/jacobian_integrator
#     out of tree against that prefix (only find_package(ClothLab)) and runs them with the
#     installed `clothlab`;
#  3. runs the installed clothlab-conformance on the examples and the plain-C test plugin (all
#     must pass), the loading and descriptor checks on every installed built-in (the test suite
#     runs every check on them), then on each deliberately faulty plugin (each must be caught by
#     its check while the run completes).
# Usage: tools/ci-sdk.sh [BUILD_DIR]   (default build; configured with tests on)
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
[ -f "$build/CMakeCache.txt" ] || { echo "ci-sdk: $build: not a configured build tree" >&2; exit 2; }

faulty=(lies_about_order produces_nan moves_pinned segfaults_in_step hangs_in_step abi_major_2
        throws_through_boundary allocates_every_step misdeclares_scheme
        claims_unconditional_stability flips_the_stiffness_sign allocates_in_worker_thread
        reserves_in_step claims_to_resolve_contacts jumps_its_collider)
cmake --build "$build" -j "$(nproc)" --target clothlab clothlab-conformance clothlab_python_package \
  euler midpoint rk4 verlet xpbd vbd sheet flag c_euler "${faulty[@]/#/faulty_}"

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
prefix="$work/prefix"
cmake --install "$build" --prefix "$prefix" >/dev/null

echo "== the installed Python module, with the installed plugins"
package=$(echo "$prefix"/lib*/python3/dist-packages)
env -u CLOTHLAB_PLUGIN_PATH PYTHONPATH="$package" /usr/bin/python3 - "$prefix" <<'PY'
import pathlib, sys
import clothlab
prefix = pathlib.Path(sys.argv[1])
assert pathlib.Path(clothlab.__file__).is_relative_to(prefix), clothlab.__file__
assert clothlab.plugins()["search_path"].startswith(str(prefix)), clothlab.plugins()["search_path"]
sim = clothlab.Simulation({"integrator": "rk4", "scenario": "sheet", "steps": 5})
assert sim.step(5) == 5 and sim.verdict.startswith("stable"), sim.verdict
PY

echo "== out-of-tree example against $prefix"
cmake -S examples/third_party_integrator -B "$work/example" -DCMAKE_PREFIX_PATH="$prefix" \
  -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$work/example" -j "$(nproc)"
example="$work/example/velocity_verlet.so"
"$prefix/bin/clothlab" --integrator="$example" --scenario=sheet
# The second example steps through the host's jacobian and reductions extensions.
cmake -S examples/jacobian_integrator -B "$work/jacobian_example" -DCMAKE_PREFIX_PATH="$prefix" \
  -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$work/jacobian_example" -j "$(nproc)"
jacobian_example="$work/jacobian_example/linearly_implicit_euler.so"
"$prefix/bin/clothlab" --integrator="$jacobian_example" --scenario=sheet --duration 0.2 --dt 0.01

conformance="$prefix/bin/clothlab-conformance"
test_plugins="$build/tests/conformance/plugins"
seed=${CLOTHLAB_CONFORMANCE_SEED:-20261125}

echo "== conformance: the examples and the C plugin must pass; every installed built-in loads"
# The installed runner on the plugins built out of tree, every check. The built-ins pass every
# check in the test suite (conformance.Conformance/SoundPlugin, the same runner from the build
# tree); here each installed one is loaded and described by the installed runner.
"$conformance" --seed "$seed" "$example" "$jacobian_example" "$test_plugins/c_euler.so" \
  >"$work/sound.txt" ||
  { cat "$work/sound.txt"; echo "ci-sdk: a sound plugin failed conformance" >&2; exit 1; }
grep -c '^PASS' "$work/sound.txt" | xargs printf '%s checks passed; summary: '
tail -n 1 "$work/sound.txt"
builtins=()
for plugin in "$prefix"/lib/clothlab/plugins/*.so; do
  builtins+=("$plugin")
done
"$conformance" --seed "$seed" --filter 'loading|descriptor' "${builtins[@]}" >"$work/builtins.txt" ||
  { cat "$work/builtins.txt"; echo "ci-sdk: an installed built-in failed loading" >&2; exit 1; }
echo "$(grep -c '^PASS' "$work/builtins.txt") loading and descriptor checks passed on ${#builtins[@]} installed built-ins"
# The mesh scenario has no file by default (its create refuses an empty scenario.file), and a
# valid parameter set may rightly refuse (a file over max_file_mb, a pin rule that selects
# nothing), so params.fuzz and scenario.params do not apply: it runs the other checks on a
# shipped mesh, as conformance.ConformanceRun.TheMeshScenarioPassesWithAFileFromTextParameters.
"$conformance" --seed "$seed" --text mesh.file="$PWD/assets/meshes/disc.obj" \
  --filter 'loading|descriptor|params[.](defaults|out-of-range|wrong-type)|scenario[.](valid|deterministic|colliders|attachments)' \
  "$prefix"/lib/clothlab/plugins/mesh.so >"$work/mesh.txt" ||
  { cat "$work/mesh.txt"; echo "ci-sdk: the mesh scenario failed conformance" >&2; exit 1; }
tail -n 1 "$work/mesh.txt"

echo "== conformance: each faulty plugin must be caught"
# plugin  component  check  extra runner options
expectations=(
  "lies_about_order|lies-about-order|numerics.order-spring|--filter numerics"
  "produces_nan|produces-nan|lifecycle.grid-3x3-f64|--filter lifecycle"
  "moves_pinned|moves-pinned|numerics.pinned-f64|--filter numerics.pinned"
  "segfaults_in_step|segfaults-in-step|lifecycle.grid-3x3-f64|--filter lifecycle.grid"
  "hangs_in_step|hangs-in-step|lifecycle.grid-3x3-f64|--timeout 1 --filter lifecycle.grid-3x3"
  "abi_major_2|library|loading.abi-version|"
  "throws_through_boundary|throws-through-boundary|robustness.no-throw|--filter robustness"
  "allocates_every_step|allocates-every-step|robustness.no-alloc|--filter robustness"
  "misdeclares_scheme|misdeclares-scheme|descriptor.extensions|--filter descriptor"
  "claims_unconditional_stability|claims-unconditional-stability|stability.unconditional-sheet|--filter stability.unconditional"
  "flips_the_stiffness_sign|flips-the-stiffness-sign|stability.default-sheet|--filter stability.default"
  "allocates_in_worker_thread|allocates-in-worker-thread|robustness.no-alloc|--filter robustness.no-alloc"
  "reserves_in_step|reserves-in-step|robustness.no-alloc|--filter robustness.no-alloc"
  "claims_to_resolve_contacts|claims-to-resolve-contacts|contacts.no-tunnelling|--filter contacts"
  "jumps_its_collider|jumps-its-collider|scenario.colliders|--filter scenario.colliders"
)
for expectation in "${expectations[@]}"; do
  IFS='|' read -r name component check options <<<"$expectation"
  status=0
  # shellcheck disable=SC2086 # options are words
  "$conformance" --seed "$seed" $options "$test_plugins/faulty_$name.so" >"$work/$name.txt" ||
    status=$?
  line=$(grep "^FAIL faulty_$name:$component $check " "$work/$name.txt" || true)
  if [ "$status" -ne 1 ] || [ -z "$line" ] || ! tail -n 1 "$work/$name.txt" | grep -q ' failed$'; then
    cat "$work/$name.txt"
    echo "ci-sdk: faulty_$name was not caught by $check (exit $status)" >&2
    exit 1
  fi
  echo "caught: $line"
done
echo "ci-sdk: all passed"
