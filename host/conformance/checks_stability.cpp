// stability.*: what an integrator declares about its stability is held against runs. One
// that declares CLOTHLAB_TRAIT_UNCONDITIONALLY_STABLE must stay stable, by the stability
// monitor's criteria (finite, stretch limit, energy bound), at dt = 50 ms for 2 s on the
// default sheet and the default flag: the built-in scenario plugins with their default
// parameters, found on the standard plugin search path.
#include <clothlab/analysis/stability_monitor.hpp>
#include <clothlab/host/plugin_library.hpp>
#include <clothlab/host/plugin_search_path.hpp>
#include <cstdio>
#include <string>

#include "check.hpp"
#include "fixtures.hpp"

namespace clothlab::conformance {
namespace {

constexpr double large_dt = 0.05;  // s: 50x the default dt, far beyond any explicit limit
constexpr double horizon = 2.0;    // s
// 40 steps of 50 ms on 2500 particles: an implicit step there costs up to ~0.4 s (CG on a
// stiff system), so the check gets six times the per-check timeout.
constexpr double timeout_scale = 6.0;

Scene default_scene(const std::string& scenario_id) {
  const host::PluginLibrary library =
      host::PluginLibrary::find(scenario_id, host::PluginSearchPath::standard({}));
  const host::ScenarioPlugin& scenario = library.scenario();
  const host::ScenarioInstance instance = scenario.create(scenario.default_params());
  return scene_from_abi(instance.describe());
}

Verdict stable_at_large_dt(const clothlab_integrator& integrator, const std::string& scenario_id,
                           Precision precision) {
  Scene scene;
  try {
    scene = default_scene(scenario_id);
  } catch (const std::exception& e) {
    throw CheckFailure("cannot load the default " + scenario_id + ": " + e.what());
  }
  Cloth cloth(scene, precision, pipeline_for(integrator));
  IntegratorInstance instance(integrator, default_values(integrator));
  instance.prepare(cloth);
  analysis::MonitorOptions every_step;
  every_step.check_interval = 1;
  analysis::StabilityMonitor monitor(cloth, 0.0, every_step);
  const int steps = static_cast<int>(horizon / large_dt + 0.5);
  for (int n = 0; n < steps; ++n) {
    clothlab_message message{};
    const double t = n * large_dt;
    const clothlab_status status =
        integrator.step(instance.handle(), &cloth.system(), t, large_dt, &message);
    require(status == CLOTHLAB_OK,
            "declares unconditional stability, but its step at t = " + std::to_string(t) +
                " s, dt = 50 ms failed: " + describe_status(status, message));
    const analysis::Verdict& verdict = monitor.check(cloth, n + 1, t + large_dt);
    require(verdict.stable, "declares unconditional stability, but at dt = 50 ms on the default " +
                                scenario_id + ": " + verdict.reason);
  }
  char detail[160];
  std::snprintf(detail, sizeof detail, "%d steps of 50 ms stable, max stretch %.3g", steps,
                cloth.max_stretch());
  return {true, detail};
}

}  // namespace

std::vector<Check> stability_checks(const clothlab_integrator& integrator) {
  const clothlab_integrator* c = &integrator;
  if (!has_trait(integrator, CLOTHLAB_TRAIT_UNCONDITIONALLY_STABLE)) return {};
  const Precision precision = preferred_precision(integrator);
  return {
      {c->id, "stability.unconditional-sheet",
       [c, precision] { return stable_at_large_dt(*c, "sheet", precision); }, timeout_scale},
      {c->id, "stability.unconditional-flag",
       [c, precision] { return stable_at_large_dt(*c, "flag", precision); }, timeout_scale},
  };
}

}  // namespace clothlab::conformance
