#include "simulation.hpp"

#include <clothlab/ext/integrator_traits.h>

#include <algorithm>
#include <chrono>
#include <clothlab/analysis/projected_area.hpp>
#include <clothlab/analysis/stability_monitor.hpp>
#include <clothlab/core/cloth_material.hpp>
#include <clothlab/core/cloth_model.hpp>
#include <clothlab/host/errors.hpp>
#include <clothlab/host/param_text.hpp>
#include <cmath>
#include <set>
#include <stdexcept>

#include "scene_air.hpp"
#include "scene_mesh.hpp"

namespace clothlab::cli {

namespace {

bool declares_param(const host::ParamSet& params, std::string_view name) {
  return std::any_of(params.specs().begin(), params.specs().end(),
                     [&](const clothlab_param_spec& spec) { return name == spec.name; });
}

// xpbd's own "substeps" (40 by default) multiplied the frame substeps; it became
// inner_substeps (default 1), so the frame substeps are the one knob. A config written for the
// old meaning would otherwise run 40 times less work without a word.
void refuse_old_substeps(const host::ParamSet& params, std::string_view id, const Setting& setting,
                         std::string_view key, const std::string& written) {
  if (params.prefix() != "integrator" || key != "substeps" || declares_param(params, "substeps") ||
      !declares_param(params, "inner_substeps"))
    return;
  throw host::InputError(setting.source + ": " + written + " = " + setting.value + ": " +
                         std::string(id) +
                         " has no substeps parameter any more; use the frame substeps (substeps: "
                         "N or --substeps N, with frame_rate), which multiply its cost as "
                         "integrator.substeps did, or integrator.inner_substeps for substeps "
                         "inside each step");
}

// Applies the plugin_params.<id>.* settings addressed to this component, then its
// integrator.* / scenario.* settings.
host::ParamSet apply(host::ParamSet params, std::string_view id,
                     const std::vector<Setting>& for_plugin_ids,
                     const std::vector<Setting>& settings) {
  const std::string prefix = std::string(id) + ".";
  for (const Setting& setting : for_plugin_ids) {
    if (!setting.key.starts_with(prefix)) continue;
    const std::string key = setting.key.substr(prefix.size());
    refuse_old_substeps(params, id, setting, key, "plugin_params." + setting.key);
    params.set(key, setting.value, setting.source);
  }
  for (const Setting& setting : settings) {
    refuse_old_substeps(params, id, setting, setting.key, params.prefix() + "." + setting.key);
    params.set(setting.key, setting.value, setting.source);
  }
  return params;
}

nlohmann::json params_to_json(const host::ParamSet& params) {
  nlohmann::json object = nlohmann::json::object();
  for (size_t i = 0; i < params.specs().size(); ++i) {
    const clothlab_param_spec& spec = params.specs()[i];
    const double* v = params.values()[i].v;
    switch (spec.type) {
      case CLOTHLAB_PARAM_INT:
        object[spec.name] = static_cast<long long>(v[0]);
        break;
      case CLOTHLAB_PARAM_BOOL:
        object[spec.name] = v[0] != 0.0;
        break;
      case CLOTHLAB_PARAM_VEC3:
        object[spec.name] = {v[0], v[1], v[2]};
        break;
      default:
        object[spec.name] = v[0];
    }
  }
  for (size_t i = 0; i < params.text_specs().size(); ++i)
    object[params.text_specs()[i].name] = params.texts()[i];
  return object;
}

// A plugin that refuses its parameter values with "invalid argument" is rejecting user
// input: report it as such (exit code 1), not as a plugin failure.
template <class Create>
auto create_with_user_params(Create&& create) {
  try {
    return create();
  } catch (const host::PluginError& error) {
    if (error.status() != CLOTHLAB_ERROR_INVALID_ARGUMENT) throw;
    throw host::InputError(std::string("parameters rejected: ") + error.what());
  }
}

bool declares_trait(const host::IntegratorPlugin& integrator, uint32_t trait) {
  const auto* traits = static_cast<const clothlab_integrator_traits*>(
      integrator.extension(CLOTHLAB_EXT_INTEGRATOR_TRAITS));
  return traits != nullptr && traits->struct_size >= sizeof(clothlab_integrator_traits) &&
         (traits->flags & trait) != 0;
}

// How often a step asks for the attachments' targets: once per substep (the count the traits'
// substeps_param names), once per step for an integrator without substeps.
uint32_t target_samples_per_step(const host::IntegratorPlugin& integrator,
                                 const host::ParamSet& params) {
  const auto* traits = static_cast<const clothlab_integrator_traits*>(
      integrator.extension(CLOTHLAB_EXT_INTEGRATOR_TRAITS));
  if (traits == nullptr || traits->struct_size < sizeof(clothlab_integrator_traits) ||
      traits->substeps_param == nullptr)
    return 1;
  return static_cast<uint32_t>(std::max(1.0, params.value(traits->substeps_param).v[0]));
}

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace

void SolverTotals::add(uint64_t step, const clothlab_solver_step_statistics& statistics) {
  ++steps;
  iterations += statistics.iterations;
  max_iterations = std::max(max_iterations, statistics.iterations);
  factorizations += statistics.factorizations;
  max_residual = std::max(max_residual, statistics.residual);
  if (statistics.converged) return;
  ++non_converged_steps;
  if (!first_non_converged_step) first_non_converged_step = step;
}

namespace {

// A plugin that cannot be loaded, or holds no plugin of the kind asked for, is reported at the
// key that named it.
template <class Load>
auto at_key(const std::string& name, const std::string& source, const char* kind, Load&& load) {
  try {
    return load();
  } catch (const host::PluginLoadError& error) {
    throw host::PluginLoadError(source + ": " + kind + " = " + name + ": " + error.what());
  }
}

// The warp/weft stretch seen at a check, and its robust figures (the percentile: a selection
// over the springs, outside the timed steps); a new largest maximum also records when and which
// spring (one more pass, only at checks that raise it). Returns the check's 99th percentile.
double note_stretch(RunRecord& record, const Cloth& cloth, const Cloth::Stretch& stretch,
                    double t) {
  const double p99 = cloth.stretch_percentile(Cloth::Springs::Structural, 0.99);
  record.p99_stretch_over_run = std::max(record.p99_stretch_over_run, p99);
  record.max_stretch_away_from_pins_over_run =
      std::max(record.max_stretch_away_from_pins_over_run, stretch.max_away_from_pins);
  if (!(stretch.max > record.max_stretch_over_run)) return p99;
  record.max_stretch_over_run = stretch.max;
  record.max_stretch_over_run_time = t;
  record.max_stretch_over_run_spring = cloth.longest_spring(Cloth::Springs::Structural);
  return p99;
}

// plugin_params.<id>.* addressed to no plugin that exists is a typo, not a setting for later.
void check_plugin_param_ids(const RunConfig& config, const LoadedPlugins& plugins,
                            const host::PluginSearchPath& search_path) {
  if (config.plugin_params.empty()) return;
  std::set<std::string, std::less<>> ids = {std::string(plugins.integrator->info().id),
                                            std::string(plugins.scenario->info().id)};
  for (const host::PluginLibrary& library : host::scan_libraries(search_path).libraries) {
    for (const host::IntegratorPlugin& plugin : library.integrators())
      ids.emplace(plugin.info().id);
    for (const host::ScenarioPlugin& plugin : library.scenarios()) ids.emplace(plugin.info().id);
  }
  for (const Setting& setting : config.plugin_params) {
    const std::string id = setting.key.substr(0, setting.key.find('.'));
    if (ids.count(id) == 0) {
      std::string known;
      for (const std::string& name : ids) known += (known.empty() ? "" : ", ") + name;
      throw host::InputError(setting.source + ": plugin_params." + setting.key +
                             ": no plugin has the id " + id + "; allowed ids: " + known);
    }
  }
}

// A solve that missed its tolerance makes the step something other than the method's: a run
// with one fails like a stability check (lab/running.md), counted, but only once it is over,
// since the state itself may be fine. A run that already failed or was interrupted, or whose
// iteration limit is a fixed budget (stability.unconverged = count), keeps its verdict, with
// the count added.
void judge_solver(RunRecord& record, bool unconverged_fails) {
  if (!record.solver || record.solver->non_converged_steps == 0) return;
  const SolverTotals& solver = *record.solver;
  const std::string missed = "the solver missed its tolerance in " +
                             std::to_string(solver.non_converged_steps) + " of " +
                             std::to_string(solver.steps) + " steps (first at step " +
                             std::to_string(*solver.first_non_converged_step) + ")";
  if (!record.stable || record.interrupted || !unconverged_fails) {
    record.verdict += "; " + missed;
    return;
  }
  record.verdict = "unconverged: " + missed + "; " + record.verdict;
  record.stable = false;
  record.failed_check = unconverged_check;
  record.failed_step = solver.first_non_converged_step;
}

std::optional<double> drape_coefficient(const Cloth& cloth) {
  const Scene& scene = cloth.scene();
  if (scene.gravity == Vec3{0, 0, 0}) return std::nullopt;
  std::vector<double> positions;
  cloth.positions(positions);
  const ClothModel& model = *cloth.model();
  if (!model.grid)
    return analysis::projected_area(positions, model.triangles, scene.gravity) /
           surface_area(model.rest_positions, model.triangles);
  return analysis::projected_area(positions, model.triangles, scene.gravity) /
         (scene.width * scene.height);
}

}  // namespace

LoadedPlugins load_plugins(const RunConfig& config, const host::PluginSearchPath& search_path) {
  host::PluginLibrary integrator_library =
      at_key(config.integrator, config.integrator_source, "integrator",
             [&] { return host::PluginLibrary::find(config.integrator, search_path); });
  host::PluginLibrary scenario_library =
      at_key(config.scenario, config.scenario_source, "scenario",
             [&] { return host::PluginLibrary::find(config.scenario, search_path); });
  const host::IntegratorPlugin* integrator =
      at_key(config.integrator, config.integrator_source, "integrator",
             [&] { return &integrator_library.integrator(); });
  const host::ScenarioPlugin* scenario = at_key(config.scenario, config.scenario_source, "scenario",
                                                [&] { return &scenario_library.scenario(); });
  host::ParamSet integrator_params = apply(integrator->default_params(), integrator->info().id,
                                           config.plugin_params, config.integrator_params);
  host::ParamSet scenario_params = apply(scenario->default_params(), scenario->info().id,
                                         config.plugin_params, config.scenario_params);
  if (config.material) {
    // Everything the user set for the scenario, by either route, may not contradict it.
    std::vector<Setting> user_settings = config.scenario_params;
    const std::string prefix = std::string(scenario->info().id) + ".";
    for (const Setting& setting : config.plugin_params)
      if (setting.key.starts_with(prefix))
        user_settings.push_back({setting.key.substr(prefix.size()), setting.value, setting.source});
    check_no_material_conflict(*config.material, user_settings);
  }
  const uint32_t precision = config.float64 ? CLOTHLAB_FLOAT64 : CLOTHLAB_FLOAT32;
  if (!integrator->supports_precision(precision))
    throw host::InputError("precision = " + std::string(config.float64 ? "float64" : "float32") +
                           ": integrator " + std::string(integrator->info().id) +
                           " does not support it");
  LoadedPlugins plugins{
      std::move(integrator_library), std::move(scenario_library), integrator, scenario,
      std::move(integrator_params),  std::move(scenario_params)};
  check_plugin_param_ids(config, plugins, search_path);
  return plugins;
}

Simulation::Simulation(const RunConfig& config, const host::PluginSearchPath& search_path)
    : Simulation(config, load_plugins(config, search_path)) {}

Simulation::Simulation(const RunConfig& config, LoadedPlugins plugins)
    : config_(config),
      integrator_library_(std::move(plugins.integrator_library)),
      scenario_library_(std::move(plugins.scenario_library)),
      integrator_(plugins.integrator),
      scenario_(plugins.scenario) {
  const host::ParamSet& integrator_params = plugins.integrator_params;
  const host::ParamSet& scenario_params = plugins.scenario_params;
  integrator_params_ = params_to_json(integrator_params);
  scenario_params_ = params_to_json(scenario_params);

  {
    scenario_instance_.emplace(
        create_with_user_params([&] { return scenario_->create(scenario_params); }));
    SceneCloth described = scene_cloth(*scenario_, *scenario_instance_);
    if (config.material) put_material(described, *config.material);
    Scene& scene = described.scene;
    attachments_ = std::make_unique<SceneAttachments>(
        *scenario_, *scenario_instance_, described.particle_count(), config.dt, config.steps,
        target_samples_per_step(*integrator_, integrator_params));
    if (!attachments_->empty() && !declares_trait(*integrator_, CLOTHLAB_TRAIT_MOVES_ATTACHMENTS))
      throw host::InputError("integrator " + std::string(integrator_->info().id) +
                             " does not move attachments (no CLOTHLAB_TRAIT_MOVES_ATTACHMENTS in "
                             "clothlab.integrator-traits/1), which scenario " +
                             std::string(scenario_->info().id) + "'s " +
                             std::to_string(attachments_->particles().size()) +
                             " attached particle(s) need");
    // An attached particle is pinned: the integrators leave it to the attachment's target.
    scene.pinned.insert(scene.pinned.end(), attachments_->particles().begin(),
                        attachments_->particles().end());
    std::sort(scene.pinned.begin(), scene.pinned.end());
    scene.pinned.erase(std::unique(scene.pinned.begin(), scene.pinned.end()), scene.pinned.end());
    scene.air = scene_air(*scenario_, *scenario_instance_);
    PipelineOptions options;
    options.velocity_forces = integrator_->uses_velocity_forces();
    options.threads = config.threads;
    options.adaptive_threads = config.adaptive_threads;
    cloth_ =
        std::make_unique<Cloth>(scene, cloth_model(described),
                                config.float64 ? Precision::Float64 : Precision::Float32, options);
    if (!attachments_->empty()) {
      attachments_->check_start(*cloth_);
      cloth_->set_attachments(attachments_->particles(), *attachments_);
      (void)cloth_->move_attachments(0.0);  // checked finite when read above
    }
  }
  colliders_ = SceneColliders(*scenario_, *scenario_instance_, config.dt, config.steps);
  if (!colliders_.empty() && !declares_trait(*integrator_, CLOTHLAB_TRAIT_RESOLVES_CONTACTS))
    throw host::InputError("integrator " + std::string(integrator_->info().id) +
                           " does not resolve contacts (no CLOTHLAB_TRAIT_RESOLVES_CONTACTS in "
                           "clothlab.integrator-traits/1), which scenario " +
                           std::string(scenario_->info().id) + "'s " +
                           std::to_string(colliders_.size()) + " collider(s) need");
  cloth_->set_colliders(colliders_.at(0.0), 0.0);
  integrator_instance_.emplace(
      create_with_user_params([&] { return integrator_->create(integrator_params); }));
  integrator_instance_->prepare(cloth_->system());
}

RunRecord Simulation::run(const RunHooks& hooks) {
  step(config_.steps, hooks);
  return record();
}

void Simulation::start(const RunHooks& hooks) {
  RunRecord& record = record_;
  record.integrator = integrator_->info().id;
  record.scenario = scenario_->info().id;
  record.integrator_library = integrator_library_.path().string();
  record.scenario_library = scenario_library_.path().string();
  record.precision = cloth_->precision();
  record.rows = cloth_->scene().rows;
  record.cols = cloth_->scene().cols;
  record.dt = config_.dt;
  record.frame_rate = config_.frame_rate;
  record.substeps = config_.substeps;
  if (config_.material) record.material = config_.material->name;
  record.steps_requested = config_.steps;
  record.threads = cloth_->threads();
  record.springs = cloth_->springs();
  record.integrator_params = integrator_params_;
  record.scenario_params = scenario_params_;
  for (auto* series : {&record.step_s, &record.internal_forces_s, &record.external_forces_s})
    series->reserve(std::min<uint64_t>(config_.steps, max_timing_samples));

  if (!colliders_.empty()) {
    record.contacts.emplace().colliders = colliders_.size();
    const std::span<const Collider> shapes = cloth_->colliders();
    record.contacts->thickness =
        std::min_element(shapes.begin(), shapes.end(), [](const Collider& a, const Collider& b) {
          return a.thickness < b.thickness;
        })->thickness;
  }
  if (!attachments_->empty())
    record.attachments.emplace().particles = attachments_->particles().size();
  // Taken at the first step, not at construction: a state the caller set before it is the
  // run's initial state.
  analysis::MonitorOptions monitor_options = config_.monitor;
  monitor_options.momentum_measures_pins =
      !declares_trait(*integrator_, CLOTHLAB_TRAIT_DRAGS_TOWARDS_REST);
  monitor_.emplace(*cloth_, 0.0, monitor_options);
  trace_energy_ = hooks.trace_energy;
  if (trace_energy_) record.energy_trace.push_back({0.0, cloth_->energy()});
  cloth_->reset_counters();
  const auto observe_start = std::chrono::steady_clock::now();
  if (hooks.observer) hooks.observer->observe(*cloth_, 0, 0.0);
  record.loop_total_s += seconds_since(observe_start);
}

void Simulation::state_written() { integrator_instance_->prepare(cloth_->system()); }

bool Simulation::finished() const {
  return record_.steps_taken >= config_.steps || !record_.stable || record_.interrupted ||
         record_.stretch_stopped;
}

uint64_t Simulation::step(uint64_t count, const RunHooks& hooks) {
  if (!monitor_) start(hooks);
  const auto loop_start = std::chrono::steady_clock::now();
  uint64_t taken = 0;
  for (; taken < count && !finished(); ++taken) {
    if (hooks.stop_requested && hooks.stop_requested->load(std::memory_order_relaxed)) {
      record_.interrupted = true;
      break;
    }
    step_once(hooks);
  }
  record_.loop_total_s += seconds_since(loop_start);
  return taken;
}

uint64_t Simulation::advance(double seconds, const RunHooks& hooks) {
  return step(steps_to_advance(seconds), hooks);
}

uint64_t Simulation::steps_to_advance(double seconds) const {
  if (!(seconds >= 0) || !std::isfinite(seconds))
    throw host::InputError("advance(" + host::format_number(seconds) +
                           " s): allowed: a finite time >= 0 s");
  // Whole steps that reach the time, without counting a rounding error in seconds / dt as a
  // step of its own.
  const double steps = std::ceil(seconds / config_.dt * (1 - 1e-12));
  return static_cast<uint64_t>(std::min(steps, static_cast<double>(steps_left())));
}

void Simulation::step_once(const RunHooks& hooks) {
  RunRecord& record = record_;
  analysis::StabilityMonitor& monitor = *monitor_;
  auto fail = [&](uint64_t step, std::string check, std::string verdict) {
    record.stable = false;
    record.failed_step = step;
    record.failed_check = std::move(check);
    record.verdict = std::move(verdict);
  };
  const clothlab_system& system = cloth_->system();
  const uint64_t step = record.steps_taken + 1;
  // t from the step count, not by summing dt, so long runs do not drift.
  const double t = static_cast<double>(step - 1) * config_.dt;
  const StageCounters before = cloth_->counters();
  const auto start = std::chrono::steady_clock::now();
  cloth_->begin_step();
  try {
    integrator_instance_->step(system, t, config_.dt);
  } catch (const host::PluginError& error) {
    if (error.status() != CLOTHLAB_ERROR_NUMERICAL) throw;
    fail(step, "non-finite",
         "non-finite state at step " + std::to_string(step) + " (" + error.what() + ")");
  }
  cloth_->end_step();
  const double step_s = seconds_since(start);
  // The colliders at the next step's start, moving at their velocity over it; the step's paths
  // are judged against them for crossings.
  const double t_end = static_cast<double>(step) * config_.dt;
  if (!colliders_.empty()) cloth_->set_colliders(colliders_.at(t_end), t_end);
  record.step_total_s += step_s;
  if ((step - 1) % record.timing_stride == 0) {
    const StageCounters& after = cloth_->counters();
    record.step_s.push_back(step_s);
    record.internal_forces_s.push_back(after.internal_forces_s - before.internal_forces_s);
    record.external_forces_s.push_back(after.external_forces_s - before.external_forces_s);
    if (record.step_s.size() == max_timing_samples) {
      // Full: keep every second sample, and from now on every second step at the new stride.
      for (auto* series : {&record.step_s, &record.internal_forces_s, &record.external_forces_s}) {
        for (size_t i = 0; 2 * i < series->size(); ++i) (*series)[i] = (*series)[2 * i];
        series->resize(series->size() / 2);
      }
      record.timing_stride *= 2;
    }
  }
  record.steps_taken = step;
  if (!record.stable) return;
  if (record.contacts) {
    const Cloth::Contacts now = cloth_->contacts();
    record.contacts->max_penetration_over_run =
        std::max(record.contacts->max_penetration_over_run, now.max_penetration);
    record.contacts->max_depth_past_thickness_over_run =
        std::max(record.contacts->max_depth_past_thickness_over_run, now.max_depth_past_thickness);
    record.contacts->crossings_over_run += now.particles_crossed;
  }
  if (const auto statistics = integrator_instance_->last_step_statistics()) {
    if (!record.solver) record.solver.emplace();
    record.solver->add(step, *statistics);
  }
  const analysis::Verdict& verdict = step == config_.steps ? monitor.check(*cloth_, step, t_end)
                                                           : monitor.observe(*cloth_, step, t_end);
  if (!verdict.stable) fail(verdict.step, analysis::to_string(verdict.fired), verdict.reason);
  // Sampled where the monitor looks, so the maximum over the run costs no extra passes
  // beyond one per check.
  if (trace_energy_ && (step % config_.monitor.check_interval == 0 || step == config_.steps))
    record.energy_trace.push_back({t_end, cloth_->energy()});
  if (step % config_.monitor.check_interval == 0 || step == config_.steps)
    note_stretch(record, *cloth_, cloth_->stretch(Cloth::Springs::Structural), t_end);
  // A run the monitor failed keeps that verdict. The stop judges the robust figure, the one
  // --choose judges.
  if (record.stable && config_.stretch_stop > 0 &&
      record.max_stretch_away_from_pins_over_run > config_.stretch_stop) {
    record.stretch_stopped = true;
    return;
  }
  if (record.stable && hooks.observer) hooks.observer->observe(*cloth_, step, t_end);
}

RunRecord Simulation::record() const {
  RunRecord record = record_;
  if (!monitor_) return record;
  const Cloth::Stretch final_stretch = cloth_->stretch(Cloth::Springs::Structural);
  record.final_stretch = final_stretch;
  record.final_p99_stretch = note_stretch(record, *cloth_, final_stretch,
                                          static_cast<double>(record.steps_taken) * config_.dt);
  record.stability_checks = monitor_->checks();
  if (record.contacts) {
    record.contacts->particles_inside_at_end = cloth_->contacts().particles_inside;
    record.contacts->drape_coefficient = drape_coefficient(*cloth_);
    record.contacts->work = cloth_->contact_work();
  }
  if (record.attachments) record.attachments->work = monitor_->attachment_work();
  if (record.interrupted)
    record.verdict = "interrupted after " + std::to_string(record.steps_taken) + " steps";
  else if (record.stretch_stopped)
    record.verdict = "stopped at step " + std::to_string(record.steps_taken) + " (t = " +
                     host::format_number(static_cast<double>(record.steps_taken) * config_.dt) +
                     " s): warp/weft stretch away from the pins " +
                     host::format_number(record.max_stretch_away_from_pins_over_run) +
                     " above stability.stretch_stop " + host::format_number(config_.stretch_stop);
  else if (record.stable)
    record.verdict = "stable: " + std::to_string(record.steps_taken) + " steps, " +
                     std::to_string(monitor_->checks()) +
                     " checks passed (finite, stretch, energy)";
  judge_solver(record, config_.unconverged_fails);
  record.counters = cloth_->counters();
  return record;
}

}  // namespace clothlab::cli
