// One run's figures, as every consumer sees them: the run JSON (--json, the frames folder's
// run.json), the case worker's answer to the parent process, sweep rows, --choose's probes and
// the work-precision trajectory cache. Each struct names its fields once, in `fields`, which
// both to_json and run_summary_from_json walk: a new figure is a member and one line there.
// docs/reference/run-json.md documents the fields.
#pragma once

#include <cmath>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <string_view>
#include <type_traits>

namespace clothlab::host {

// Whether a field is optional (null in the JSON when empty): the writer, the reader and the
// test that every member is in its table all walk into an optional's value.
template <class T>
struct is_optional : std::false_type {};
template <class T>
struct is_optional<std::optional<T>> : std::true_type {};

struct RunSummary {
  // Wall time of one step or one frame over the run, ms.
  struct Spread {
    double median = 0, p10 = 0, p90 = 0;
    template <class Self, class Visit>
    static void fields(Self& self, Visit& visit) {
      visit("median", self.median);
      visit("p10", self.p10);
      visit("p90", self.p90);
    }
    bool operator==(const Spread&) const = default;
  };
  // The median step's phases, ms.
  struct Phases {
    double internal_forces = 0, external_forces = 0, integrate = 0;
    template <class Self, class Visit>
    static void fields(Self& self, Visit& visit) {
      visit("internal_forces", self.internal_forces);
      visit("external_forces", self.external_forces);
      visit("integrate", self.integrate);
    }
    bool operator==(const Phases&) const = default;
  };
  // Where and when the largest stretch over the run was seen: a grid's spring by rows and
  // columns, another mesh's by particle indices (the other pair is absent).
  struct SpringSeen {
    double t = 0;
    std::optional<uint64_t> row, col, to_row;
    std::optional<int64_t> to_col;
    std::optional<uint64_t> particle, to_particle;
    template <class Self, class Visit>
    static void fields(Self& self, Visit& visit) {
      visit("t", self.t);
      visit.absent_when_empty("row", self.row);
      visit.absent_when_empty("col", self.col);
      visit.absent_when_empty("to_row", self.to_row);
      visit.absent_when_empty("to_col", self.to_col);
      visit.absent_when_empty("particle", self.particle);
      visit.absent_when_empty("to_particle", self.to_particle);
    }
    bool operator==(const SpringSeen&) const = default;
  };
  // Structural (warp/weft) spring length over rest length: at the end and the largest seen at
  // the stability checks (null when not finite: a diverged run's).
  struct Stretch {
    double final = 1, over_run = 1;
    template <class Self, class Visit>
    static void fields(Self& self, Visit& visit) {
      visit("final", self.final);
      visit("over_run", self.over_run);
    }
    bool operator==(const Stretch&) const = default;
  };
  struct MaxStretch {
    double final = 1, over_run = 1;
    std::optional<SpringSeen> over_run_at;  // absent while no check saw a spring stretched
    template <class Self, class Visit>
    static void fields(Self& self, Visit& visit) {
      visit("final", self.final);
      visit("over_run", self.over_run);
      visit.absent_when_empty("over_run_at", self.over_run_at);
    }
    bool operator==(const MaxStretch&) const = default;
  };
  struct IterationsPerStep {
    double mean = 0;
    uint64_t max = 0;
    template <class Self, class Visit>
    static void fields(Self& self, Visit& visit) {
      visit("mean", self.mean);
      visit("max", self.max);
    }
    bool operator==(const IterationsPerStep&) const = default;
  };
  // An iterative or factorising integrator's statistics (clothlab.solver-statistics/1).
  struct Solver {
    uint64_t steps = 0, iterations = 0;
    IterationsPerStep iterations_per_step;
    uint64_t factorizations = 0, non_converged_steps = 0;
    std::optional<uint64_t> first_non_converged_step;
    double max_residual = 0;
    template <class Self, class Visit>
    static void fields(Self& self, Visit& visit) {
      visit("steps", self.steps);
      visit("iterations", self.iterations);
      visit("iterations_per_step", self.iterations_per_step);
      visit("factorizations", self.factorizations);
      visit("non_converged_steps", self.non_converged_steps);
      visit("first_non_converged_step", self.first_non_converged_step);
      visit("max_residual", self.max_residual);
    }
    bool operator==(const Solver&) const = default;
  };
  // A scene with colliders (m, J).
  struct Contacts {
    uint64_t colliders = 0;
    double max_penetration_over_run = 0, max_depth_past_thickness_over_run = 0, thickness = 0;
    uint64_t particles_inside_at_end = 0, crossings_over_run = 0;
    std::optional<double> drape_coefficient;  // empty without gravity
    double work = 0;
    template <class Self, class Visit>
    static void fields(Self& self, Visit& visit) {
      visit("colliders", self.colliders);
      visit("max_penetration_over_run", self.max_penetration_over_run);
      visit("max_depth_past_thickness_over_run", self.max_depth_past_thickness_over_run);
      visit("thickness", self.thickness);
      visit("particles_inside_at_end", self.particles_inside_at_end);
      visit("crossings_over_run", self.crossings_over_run);
      visit("drape_coefficient", self.drape_coefficient);
      visit("work", self.work);
    }
    bool operator==(const Contacts&) const = default;
  };
  // A scene with attachments: the work they did on the cloth (J).
  struct Attachments {
    uint64_t particles = 0;
    double work = 0;
    template <class Self, class Visit>
    static void fields(Self& self, Visit& visit) {
      visit("particles", self.particles);
      visit("work", self.work);
    }
    bool operator==(const Attachments&) const = default;
  };
  // Work counters of the engine's stages.
  struct Counters {
    uint64_t springs_evaluated = 0, springs_damped = 0, normals_computed = 0,
             particles_integrated = 0, steps_on_one_thread = 0;
    template <class Self, class Visit>
    static void fields(Self& self, Visit& visit) {
      visit("springs_evaluated", self.springs_evaluated);
      visit("springs_damped", self.springs_damped);
      visit("normals_computed", self.normals_computed);
      visit("particles_integrated", self.particles_integrated);
      visit("steps_on_one_thread", self.steps_on_one_thread);
    }
    bool operator==(const Counters&) const = default;
  };

  std::string integrator, scenario, integrator_library, scenario_library;
  std::string precision;  // "float32" or "float64"
  uint64_t rows = 0, cols = 0;
  double dt = 0, frame_rate = 0;
  uint64_t substeps = 1;
  std::optional<std::string> material;
  uint64_t steps = 0, steps_requested = 0;
  double sim_time_s = 0, wall_time_s = 0, loop_time_s = 0;
  Spread ms_per_step;
  Phases phase_ms;
  Spread ms_per_frame;
  double frames_per_second = 0;
  MaxStretch max_stretch;
  Stretch max_stretch_away_from_pins, p99_stretch;
  double mean_stretch = 1;
  uint64_t springs = 0, force_evals = 0;
  double springs_per_second = 0, real_time_factor = 0;
  bool stable = true, interrupted = false, stretch_stopped = false;
  std::string verdict;
  std::optional<std::string> failed_check;
  std::optional<uint64_t> failed_step;
  uint64_t stability_checks = 0;
  std::optional<Solver> solver;
  std::optional<Contacts> contacts;
  std::optional<Attachments> attachments;
  int64_t threads = 0;
  std::string simd;  // the SIMD target the core's kernels ran on
  Counters counters;
  nlohmann::json integrator_params = nlohmann::json::object();
  nlohmann::json scenario_params = nlohmann::json::object();

  template <class Self, class Visit>
  static void fields(Self& self, Visit& visit) {
    visit("integrator", self.integrator);
    visit("scenario", self.scenario);
    visit("integrator_library", self.integrator_library);
    visit("scenario_library", self.scenario_library);
    visit("precision", self.precision);
    visit("rows", self.rows);
    visit("cols", self.cols);
    visit("dt", self.dt);
    visit("frame_rate", self.frame_rate);
    visit("substeps", self.substeps);
    visit("material", self.material);
    visit("steps", self.steps);
    visit("steps_requested", self.steps_requested);
    visit("sim_time_s", self.sim_time_s);
    visit("wall_time_s", self.wall_time_s);
    visit("loop_time_s", self.loop_time_s);
    visit("ms_per_step", self.ms_per_step);
    visit("phase_ms", self.phase_ms);
    visit("ms_per_frame", self.ms_per_frame);
    visit("frames_per_second", self.frames_per_second);
    visit("max_stretch", self.max_stretch);
    visit("max_stretch_away_from_pins", self.max_stretch_away_from_pins);
    visit("p99_stretch", self.p99_stretch);
    visit("mean_stretch", self.mean_stretch);
    visit("springs", self.springs);
    visit("force_evals", self.force_evals);
    visit("springs_per_second", self.springs_per_second);
    visit("real_time_factor", self.real_time_factor);
    visit("stable", self.stable);
    visit("interrupted", self.interrupted);
    visit("stretch_stopped", self.stretch_stopped);
    visit("verdict", self.verdict);
    visit("failed_check", self.failed_check);
    visit("failed_step", self.failed_step);
    visit("stability_checks", self.stability_checks);
    visit("solver", self.solver);
    visit("contacts", self.contacts);
    visit("attachments", self.attachments);
    visit("threads", self.threads);
    visit("simd", self.simd);
    visit("counters", self.counters);
    visit("integrator_params", self.integrator_params);
    visit("scenario_params", self.scenario_params);
  }
  // The figures of the attachments and contacts, with what a scene without them has: no
  // attached particles or colliders, NAN penetrations and thickness (m).
  uint64_t attached_particles() const { return attachments ? attachments->particles : 0; }
  uint64_t colliders() const { return contacts ? contacts->colliders : 0; }
  double max_penetration() const { return contacts ? contacts->max_penetration_over_run : NAN; }
  double max_depth_past_thickness() const {
    return contacts ? contacts->max_depth_past_thickness_over_run : NAN;
  }
  double collider_thickness() const { return contacts ? contacts->thickness : NAN; }

  // The stretch figures over the run, by the names that sweep rows, --choose's probes and
  // choices and the work-precision reference row carry them: a new one is one line here.
  template <class Visit>
  void visit_stretch_over_run(Visit&& visit) const {
    visit("max_stretch", max_stretch.over_run);
    visit("max_stretch_away_from_pins", max_stretch_away_from_pins.over_run);
    visit("p99_stretch", p99_stretch.over_run);
  }

  // Compares NaN figures (a diverged run's) as unequal, like the numbers themselves.
  bool operator==(const RunSummary&) const = default;
};

// The run JSON: every field of the table, null where an optional figure is empty; a number
// that is not finite stays NaN in the object and is written as null by dump().
nlohmann::json to_json(const RunSummary& summary);

// Reads what to_json wrote; a null number reads as NaN. Throws InputError, one line naming the
// source and the field ("SOURCE: run summary field 'contacts.work': missing"), for a missing
// or unknown field or a value of the wrong type.
RunSummary run_summary_from_json(const nlohmann::json& json, std::string_view source);

}  // namespace clothlab::host
