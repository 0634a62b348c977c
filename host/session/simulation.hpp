// One run: scenario plugin -> scene -> Cloth -> integrator plugin -> timed steps, taken all
// at once (run) or a few at a time by a caller that looks at and changes the state between them.
#pragma once

#include <atomic>
#include <clothlab/analysis/stability_monitor.hpp>
#include <clothlab/core/cloth.hpp>
#include <clothlab/host/param_set.hpp>
#include <clothlab/host/plugin_library.hpp>
#include <clothlab/host/plugin_search_path.hpp>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "run_config.hpp"
#include "scene_attachments.hpp"
#include "scene_colliders.hpp"

namespace clothlab::cli {

// What an iterative or factorising integrator reported over a run
// (clothlab.solver-statistics/1), step by step.
struct SolverTotals {
  uint64_t steps = 0;  // steps reported
  uint64_t iterations = 0;
  uint64_t max_iterations = 0;  // in one step
  uint64_t factorizations = 0;
  uint64_t non_converged_steps = 0;  // steps whose solve missed its tolerance
  std::optional<uint64_t> first_non_converged_step;
  double max_residual = 0;  // relative, over all steps

  void add(uint64_t step, const clothlab_solver_step_statistics& statistics);
};

// The failed_check of a run whose solver missed its tolerance in some step.
inline constexpr const char* unconverged_check = "unconverged";

inline constexpr size_t max_timing_samples = size_t{1} << 20;

// What a run measured; the raw material of the summary.
struct RunRecord {
  std::string integrator, scenario;  // component ids
  std::string integrator_library, scenario_library;
  Precision precision = Precision::Float32;
  uint32_t rows = 0, cols = 0;
  double dt = 0;
  double frame_rate = 0;  // Hz
  uint64_t substeps = 1;  // steps per frame
  std::string material;   // the material's name; empty without one
  uint64_t steps_requested = 0;
  uint64_t steps_taken = 0;  // includes a failed step
  int threads = 0;
  SpringCounts springs;
  StageCounters counters;
  // Per step, seconds: the whole step and the core's force phases within it. At most
  // max_timing_samples steps are kept, at an even stride over the run (10^9 steps would
  // otherwise need ~24 GB); step_total_s sums every step.
  std::vector<double> step_s, internal_forces_s, external_forces_s;
  uint64_t timing_stride = 1;  // the kept samples are steps 1, 1 + stride, 1 + 2 stride, ...
  double step_total_s = 0;
  // The whole step loop: steps, stability checks and observers (--frames: the state copies
  // and any wait for the writer), which step_total_s leaves out.
  double loop_total_s = 0;
  bool stable = true;
  bool interrupted = false;      // stopped early on request (SIGINT), not by a failed check
  bool stretch_stopped = false;  // ended early by stability.stretch_stop, not by a failed check
  std::string verdict;
  // "non-finite", "stretch", "energy", "unconverged" (judged after the last step); empty while
  // stable.
  std::string failed_check;
  std::optional<uint64_t> failed_step;
  uint64_t stability_checks = 0;
  // Structural spring length / rest length (warp and weft): at the end, and the largest seen
  // at the monitor's checks.
  Cloth::Stretch final_stretch;
  double max_stretch_over_run = 1.0;
  // When and where that largest one was seen (the spring is structural); unset while no check
  // saw a spring beyond its rest length.
  std::optional<double> max_stretch_over_run_time;
  Cloth::LongestSpring max_stretch_over_run_spring;
  // The robust figures beside the maximum (issue 21), the largest seen at the checks: the
  // warp/weft stretch's 99th percentile (nearest rank) and its maximum over the springs away
  // from the pins (Cloth::Stretch::max_away_from_pins). The final state's percentile.
  double p99_stretch_over_run = 1.0;
  double max_stretch_away_from_pins_over_run = 1.0;
  double final_p99_stretch = 1.0;
  struct EnergySample {
    double t;
    Cloth::Energy energy;
  };
  std::vector<EnergySample> energy_trace;
  std::optional<SolverTotals> solver;  // only for integrators that report solver statistics
  // Scenes with colliders (clothlab.colliders/1) only.
  struct ContactFigures {
    std::size_t colliders = 0;
    // m, into a collider's surface, after any step, where the step's last contact resolution
    // met the collider.
    double max_penetration_over_run = 0;
    // The largest depth past the thickness of the collider a particle lay in, after any step
    // (m): it went through the band the contacts keep clear, what `clothlab --choose` judges
    // (no tunnelling).
    double max_depth_past_thickness_over_run = 0;
    double thickness = 0;  // the thinnest collider's (m)
    uint32_t particles_inside_at_end = 0;
    // Over the steps, the particles whose path over the step, relative to a collider, passed
    // through it or past its middle (Cloth::Contacts::particles_crossed): tunnelled.
    uint64_t crossings_over_run = 0;
    // The cloth's shadow on the plane normal to gravity over its flat area at the end (the
    // Cusick drape coefficient's projected area share); null without gravity.
    std::optional<double> drape_coefficient;
    // The energy the contact resolution added over the run (J, Cloth::contact_work), which the
    // stability monitor's energy bound allows for.
    double work = 0;
  };
  std::optional<ContactFigures> contacts;
  // Scenes with attachments (clothlab.attachments/1) only.
  struct AttachmentFigures {
    std::size_t particles = 0;
    // The work the moving attachments did on the cloth over the run (J; negative when they
    // took energy out), which the stability monitor's energy bound allows for.
    double work = 0;
  };
  std::optional<AttachmentFigures> attachments;
  nlohmann::json integrator_params, scenario_params;
};

// The plugins of a run, loaded, with the run's parameter values applied and checked.
struct LoadedPlugins {
  host::PluginLibrary integrator_library, scenario_library;
  const host::IntegratorPlugin* integrator;
  const host::ScenarioPlugin* scenario;
  host::ParamSet integrator_params, scenario_params;
};

// The checks a run's settings get before it starts, the same for a single run and for every
// case of a sweep: both plugins load (PluginLoadError naming the setting's source), their
// parameters accept the values (InputError), the integrator supports the precision, and every
// plugin_params.<id> names a plugin that exists (a typo'd id is an InputError).
LoadedPlugins load_plugins(const RunConfig& config, const host::PluginSearchPath& search_path);

// Sees the state before the first step (step 0) and after every step that passed the
// stability checks, on the stepping thread (frames output).
class StepObserver {
 public:
  virtual ~StepObserver() = default;
  virtual void observe(const Cloth& cloth, uint64_t step, double t) = 0;
};

struct RunHooks {
  StepObserver* observer = nullptr;
  // Checked before every step; once true the run stops with a verdict saying so.
  const std::atomic<bool>* stop_requested = nullptr;
  // Energy at t = 0 and at every monitor check into the record's energy_trace (an extra pass
  // over the springs there, outside the timed steps).
  bool trace_energy = false;
};

class Simulation {
 public:
  // Loads both plugins (PluginLoadError), applies the parameter settings (InputError),
  // creates the scene, the cloth and the integrator (PluginError).
  Simulation(const RunConfig& config, const host::PluginSearchPath& search_path);
  // The same with the plugins already loaded (load_plugins).
  Simulation(const RunConfig& config, LoadedPlugins plugins);

  // Steps until done or until a stability check fails (the run stops there: past a failed
  // check the numbers mean nothing). A numerical failure is a verdict, any other plugin error
  // is thrown. The monitor (config.stability.*) checks every few steps and after the last.
  // The same as step(config.steps) then record().
  RunRecord run(const RunHooks& hooks = {});

  // Takes up to `count` more steps of the run, fewer where it ends: at its last step (the
  // config's steps or duration), a failed check, a stop request or stability.stretch_stop.
  // Returns the steps taken. The first call starts the run: the monitor takes the state then
  // as the initial one, and `hooks.trace_energy` is read.
  uint64_t step(uint64_t count, const RunHooks& hooks = {});
  // Steps until the time has grown by `seconds`, rounded up to whole steps, or the run ends.
  // Throws InputError for a negative or non-finite time.
  uint64_t advance(double seconds, const RunHooks& hooks = {});
  // The steps advance(seconds) takes from here.
  uint64_t steps_to_advance(double seconds) const;
  // Simulated time: steps taken times dt.
  double time() const { return static_cast<double>(record_.steps_taken) * config_.dt; }
  uint64_t steps_taken() const { return record_.steps_taken; }
  uint64_t steps_left() const { return finished() ? 0 : config_.steps - record_.steps_taken; }
  // No check failed so far.
  bool stable() const { return record_.stable; }
  // At its last step, or stopped early by a failed check, a stop request or the stretch stop.
  bool finished() const;
  // The run so far, with the figures of its end (final stretch, verdict, the solver's judgement)
  // taken from the state now: after the last step, what run() returns.
  RunRecord record() const;

  // Writable between steps (an experiment's perturbation): the next step starts from it once
  // state_written() has told the integrator.
  Cloth& cloth() { return *cloth_; }
  // The state was written from outside: the integrator drops its history (Verlet's last
  // displacement, a multistep method's past steps) and starts again from the state as it is,
  // as after its first prepare. Each call may allocate the integrator's scratch again.
  void state_written();
  const RunConfig& config() const { return config_; }
  const Cloth& cloth() const { return *cloth_; }
  std::string integrator_id() const { return std::string(integrator_->info().id); }
  const host::IntegratorPlugin& integrator() const { return *integrator_; }
  std::string scenario_id() const { return std::string(scenario_->info().id); }
  // The parameter values in force, defaults included.
  const nlohmann::json& integrator_params() const { return integrator_params_; }
  const nlohmann::json& scenario_params() const { return scenario_params_; }

 private:
  RunConfig config_;
  host::PluginLibrary integrator_library_;
  host::PluginLibrary scenario_library_;
  const host::IntegratorPlugin* integrator_;
  const host::ScenarioPlugin* scenario_;
  nlohmann::json integrator_params_, scenario_params_;
  // The scenario lives through the run: its colliders' poses are asked for step by step.
  std::optional<host::ScenarioInstance> scenario_instance_;
  SceneColliders colliders_;
  // Held by pointer: the cloth keeps its address as the source of the attachments' targets.
  std::unique_ptr<SceneAttachments> attachments_;
  // Declared after the cloth so it is destroyed first: it may hold the system's vectors.
  std::unique_ptr<Cloth> cloth_;
  std::optional<host::IntegratorInstance> integrator_instance_;
  // The run so far; the monitor exists from the first step on.
  RunRecord record_;
  std::optional<analysis::StabilityMonitor> monitor_;
  bool trace_energy_ = false;

  void start(const RunHooks& hooks);
  void step_once(const RunHooks& hooks);
};

}  // namespace clothlab::cli
