// stability.*: every integrator runs what a user runs first, `clothlab --integrator ID
// --scenario sheet` (and flag), and must end it stable: the scene's defaults, the integrator's
// default parameters, the clothlab CLI's default dt, precision and stability monitor (its
// configuration with no setting, cli::resolve_run_config), for default_run_steps steps.
// What an integrator declares about its stability is held against runs too: one that declares
// CLOTHLAB_TRAIT_UNCONDITIONALLY_STABLE must stay stable, by the same monitor's criteria (finite,
// stretch limit, energy bound) checked every step, at dt = 50 ms for 2 s on the default sheet and
// flag. Default scenes are the built-in scenario plugins with their default parameters, found on
// the standard plugin search path.
#include <clothlab/analysis/stability_monitor.hpp>
#include <clothlab/host/param_text.hpp>
#include <clothlab/host/plugin_library.hpp>
#include <clothlab/host/plugin_search_path.hpp>
#include <cstdio>
#include <string>

#include "check.hpp"
#include "fixtures.hpp"
#include "run_config.hpp"

namespace clothlab::conformance {
namespace {

constexpr double large_dt = 0.05;  // s: 50x the default dt, far beyond any explicit limit
constexpr double horizon = 2.0;    // s
// 40 steps of 50 ms on 2500 particles: an implicit step there costs up to ~0.4 s (CG on a
// stiff system), so the check gets six times the per-check timeout.
constexpr double timeout_scale = 6.0;
// A short run: a blow-up at the default dt shows within tens of steps (a sign error in an
// implicit method's stiffness term grows the sheet's stiff modes every step), and the check
// stays cheap enough for every integrator on every CI run. An xpbd or implicit step on the
// default 2500 particles costs up to ~10 ms of CPU, several times that in wall time on a shared
// machine: twice the per-check timeout.
constexpr int default_run_steps = 50;
constexpr double default_run_timeout_scale = 2.0;

Scene default_scene(const std::string& scenario_id) {
  const host::PluginLibrary library =
      host::PluginLibrary::find(scenario_id, host::PluginSearchPath::standard({}));
  const host::ScenarioPlugin& scenario = library.scenario();
  const host::ScenarioInstance instance = scenario.create(scenario.default_params());
  return scene_from_abi(instance.describe());
}

// `steps` steps of dt on the default scene under `monitor` (its verdict after every step it
// looks at, and after the last); a failed step or verdict fails the check, prefixed by `claim`.
Verdict stable_on_default_scene(const clothlab_integrator& integrator,
                                const std::string& scenario_id, Precision precision, double dt,
                                int steps, const analysis::MonitorOptions& options,
                                const std::string& claim) {
  Scene scene;
  try {
    scene = default_scene(scenario_id);
  } catch (const std::exception& e) {
    throw CheckFailure("cannot load the default " + scenario_id + ": " + e.what());
  }
  Cloth cloth(scene, precision, pipeline_for(integrator));
  IntegratorInstance instance(integrator, default_values(integrator));
  instance.prepare(cloth);
  analysis::StabilityMonitor monitor(cloth, 0.0, options);
  const std::string where = " at dt = " + host::format_number(dt) + " s on the default " +
                            scenario_id + " (" + to_string(precision) + ")";
  for (int n = 0; n < steps; ++n) {
    clothlab_message message{};
    const double t = n * dt;
    const clothlab_status status =
        integrator.step(instance.handle(), &cloth.system(), t, dt, &message);
    require(status == CLOTHLAB_OK, claim + "its step " + std::to_string(n + 1) + where +
                                       " failed: " + describe_status(status, message));
    const uint64_t step = static_cast<uint64_t>(n) + 1;
    const analysis::Verdict& verdict =
        n + 1 == steps ? monitor.check(cloth, step, t + dt) : monitor.observe(cloth, step, t + dt);
    require(verdict.stable, claim + "it diverged" + where + ": " + verdict.reason);
  }
  char detail[200];
  std::snprintf(detail, sizeof detail, "%d steps of %s s stable (%llu checks), max stretch %.3g",
                steps, host::format_number(dt).c_str(),
                static_cast<unsigned long long>(monitor.checks()), cloth.max_stretch());
  return {true, detail};
}

Verdict stable_at_large_dt(const clothlab_integrator& integrator, const std::string& scenario_id,
                           Precision precision) {
  analysis::MonitorOptions every_step;
  every_step.check_interval = 1;
  return stable_on_default_scene(integrator, scenario_id, precision, large_dt,
                                 static_cast<int>(horizon / large_dt + 0.5), every_step,
                                 "declares unconditional stability, but ");
}

// What `clothlab --integrator ID --scenario SCENARIO` runs, cut to default_run_steps steps.
Verdict stable_as_the_cli_runs_it(const clothlab_integrator& integrator,
                                  const std::string& scenario_id) {
  const cli::RunConfig defaults = cli::resolve_run_config({});
  const uint32_t precision = defaults.float64 ? CLOTHLAB_FLOAT64 : CLOTHLAB_FLOAT32;
  const Precision run_precision = (integrator.precisions & (1u << precision)) != 0
                                      ? (defaults.float64 ? Precision::Float64 : Precision::Float32)
                                      : preferred_precision(integrator);
  return stable_on_default_scene(integrator, scenario_id, run_precision, defaults.dt,
                                 default_run_steps, defaults.monitor, "");
}

}  // namespace

std::vector<Check> stability_checks(const clothlab_integrator& integrator) {
  const clothlab_integrator* c = &integrator;
  std::vector<Check> checks = {
      {c->id, "stability.default-sheet", [c] { return stable_as_the_cli_runs_it(*c, "sheet"); },
       default_run_timeout_scale},
      {c->id, "stability.default-flag", [c] { return stable_as_the_cli_runs_it(*c, "flag"); },
       default_run_timeout_scale},
  };
  if (!has_trait(integrator, CLOTHLAB_TRAIT_UNCONDITIONALLY_STABLE)) return checks;
  const Precision precision = preferred_precision(integrator);
  checks.push_back({c->id, "stability.unconditional-sheet",
                    [c, precision] { return stable_at_large_dt(*c, "sheet", precision); },
                    timeout_scale});
  checks.push_back({c->id, "stability.unconditional-flag",
                    [c, precision] { return stable_at_large_dt(*c, "flag", precision); },
                    timeout_scale});
  return checks;
}

}  // namespace clothlab::conformance
