#include "clothlab/sweep/work_precision.hpp"

#include <algorithm>
#include <clothlab/analysis/order_fit.hpp>
#include <clothlab/host/param_text.hpp>
#include <cmath>
#include <map>

#include "clothlab/sweep/case_attempt.hpp"
#include "clothlab/sweep/sweep_error.hpp"
#include "clothlab/sweep/sweep_runner.hpp"

namespace clothlab::sweep {
namespace {

using Coordinates = std::vector<std::pair<std::string, std::string>>;

// The case's coordinates without integrator and precision: what one reference serves.
Coordinates problem_coordinates(const CaseSpec& c) {
  Coordinates kept;
  for (const auto& coordinate : c.coordinates) {
    if (coordinate.first != "integrator" && coordinate.first != "precision") {
      kept.push_back(coordinate);
    }
  }
  return kept;
}

std::string join(const Coordinates& coordinates) {
  std::string key;
  for (const auto& [name, value] : coordinates)
    key += (key.empty() ? "" : ";") + name + "=" + value;
  return key;
}

bool is_self_referenced(const WorkPrecisionSettings& wp, const CaseSpec& c) {
  return std::find(wp.self_reference.begin(), wp.self_reference.end(), c.integrator) !=
         wp.self_reference.end();
}

std::string reference_integrator(const WorkPrecisionSettings& wp, const CaseSpec& c) {
  return is_self_referenced(wp, c) ? c.integrator : wp.reference_integrator;
}

std::string reference_key(const WorkPrecisionSettings& wp, const CaseSpec& c) {
  const std::string key = "work-precision;reference;" + join(problem_coordinates(c));
  return is_self_referenced(wp, c) ? key + ";integrator=" + c.integrator : key;
}
std::string precision_floor_key(const WorkPrecisionSettings& wp, const CaseSpec& c) {
  return "work-precision;precision-floor;" + join(problem_coordinates(c)) +
         ";integrator=" + reference_integrator(wp, c) + ";precision=" + c.precision;
}
std::string ladder_key(const CaseSpec& c, double dt) {
  return "work-precision;ladder;" + c.key + ";dt=" + host::format_number(dt);
}
std::string fit_key(const CaseSpec& c) { return "work-precision;fit;" + c.key; }

double ladder_dt(const WorkPrecisionSettings& wp, int level) {
  return std::ldexp(wp.dt_start, -level);
}

bool is_whole_number_of_steps(double duration, double dt) {
  const double steps = duration / dt;
  const double rounded = std::round(steps);
  return rounded >= 1.0 && std::abs(steps - rounded) <= 1e-6 * rounded;
}

uint64_t whole_steps(double duration, double dt) {
  if (!is_whole_number_of_steps(duration, dt)) {
    throw SweepError("work-precision: duration " + host::format_number(duration) +
                     " s is not a whole number of steps of " + host::format_number(dt) +
                     " s; choose dt_start, refinement and duration so that it is");
  }
  return static_cast<uint64_t>(std::round(duration / dt));
}

CaseSpec run_spec(const CaseSpec& base, double dt, double duration) {
  return with_setting(with_dt(base, dt), "steps", std::to_string(whole_steps(duration, dt)), false);
}

// Where the case's setting of key was made (the last one: later settings win).
std::string source_of(const SweepSpec& spec, const CaseSpec& c, const std::string& key) {
  for (auto setting = c.settings.rbegin(); setting != c.settings.rend(); ++setting)
    if (setting->key == key) return setting->source;
  return spec.source;
}

double duration_of(const SweepSpec& spec, const CaseSpec& c) {
  if (c.duration > 0.0) return c.duration;
  throw SweepError(source_of(spec, c, "steps") + ": steps = " + c.setting("steps") +
                   ": work-precision runs each case to a time T; allowed: duration (T, s) "
                   "instead of steps");
}

// A row about base's problem (its coordinates without integrator and precision), run by
// `integrator`.
Row problem_row(const std::string& key, const std::string& kind, const CaseSpec& base,
                const std::string& integrator) {
  Row row;
  row["key"] = key;
  row["kind"] = kind;
  for (const auto& [name, value] : problem_coordinates(base)) row[name] = value;
  row["reference_integrator"] = integrator;
  return row;
}

}  // namespace

Trajectory compute_reference(const SweepSpec& spec, const CaseSpec& base, double dt,
                             const TrajectoryRunner& runner, ResultsStore& store) {
  const auto& wp = spec.work_precision;
  const double duration = duration_of(spec, base);
  const std::string integrator = reference_integrator(wp, base);
  CaseSpec reference = with_setting(base, "integrator.plugin", integrator);
  reference = with_setting(reference, "precision", "float64");
  const Trajectory coarse = attempt_trajectory(runner, run_spec(reference, dt, duration));
  const Trajectory fine = attempt_trajectory(runner, run_spec(reference, dt / 2.0, duration));
  for (const Trajectory* run : {&coarse, &fine}) {
    if (!run->verdict.stable()) {
      throw SweepError("work-precision: reference " + integrator + " float64 for " +
                       join(problem_coordinates(base)) + " is " + to_string(run->verdict.status) +
                       ": " + run->verdict.reason);
    }
  }
  const double difference = relative_rms_error(coarse.positions, fine.positions, fine.diagonal);
  if (!store.contains(reference_key(wp, base))) {
    Row row = problem_row(reference_key(wp, base), "reference", base, integrator);
    row["reference_dt"] = dt / 2.0;
    row["check_dt"] = dt;
    row["T"] = duration;
    row["reference_difference"] = difference;
    // The finer run's own error for an order-4 reference: difference / (2^4 - 1). A self
    // reference's order is what is being measured, so it gets no estimate.
    row["reference_error_estimate"] = is_self_referenced(wp, base) ? Row() : Row(difference / 15.0);
    row["wall_s"] = coarse.summary.wall_time_s + fine.summary.wall_time_s;
    // The converged model's own stretch over the run: what a method's is held to (--choose).
    fine.summary.visit_stretch_over_run([&](const char* name, double value) { row[name] = value; });
    store.append(row, base.index);
  }
  return fine;
}

double compute_precision_floor(const SweepSpec& spec, const CaseSpec& base, double dt,
                               const Trajectory& reference, const TrajectoryRunner& runner,
                               ResultsStore& store) {
  if (base.precision == "float64") return 0.0;
  const auto& wp = spec.work_precision;
  const double duration = duration_of(spec, base);
  const std::string integrator = reference_integrator(wp, base);
  const CaseSpec same_step =
      run_spec(with_setting(base, "integrator.plugin", integrator), dt / 2.0, duration);
  const Trajectory run = attempt_trajectory(runner, same_step);
  if (!run.verdict.stable())
    throw SweepError("work-precision: " + integrator + " " + base.precision + " at dt " +
                     host::format_number(dt / 2.0) + " s, the reference's step, for " +
                     join(problem_coordinates(base)) + " is " + to_string(run.verdict.status) +
                     ": " + run.verdict.reason);
  const double floor = relative_rms_error(run.positions, reference.positions, reference.diagonal);
  if (!store.contains(precision_floor_key(wp, base))) {
    Row row = problem_row(precision_floor_key(wp, base), "precision_floor", base, integrator);
    row["precision"] = base.precision;
    row["dt"] = dt / 2.0;
    row["T"] = duration;
    row["precision_floor"] = floor;
    row["wall_s"] = run.summary.wall_time_s;
    store.append(row, base.index);
  }
  return floor;
}

namespace {

Row ladder_row(const CaseSpec& c, double dt, double duration, const Trajectory& run,
               const Trajectory& reference) {
  Row row;
  row["key"] = ladder_key(c, dt);
  row["kind"] = "ladder";
  for (const auto& [name, value] : c.coordinates) row[name] = value;
  row["dt"] = dt;
  row["steps"] = whole_steps(duration, dt);
  row["T"] = duration;
  CaseResult verdict = run.verdict;
  row["error"] = nullptr;
  if (verdict.stable()) {
    try {
      row["error"] = relative_rms_error(run.positions, reference.positions, reference.diagonal);
    } catch (const SweepError& error) {
      verdict.status = CaseStatus::Failed;
      verdict.reason = error.what();
    }
  }
  row["status"] = to_string(verdict.status);
  row["stable"] = verdict.stable();
  row["wall_per_sim_s"] = run.summary.wall_time_s / duration;
  row["force_evals"] = run.summary.force_evals;
  row["check"] = verdict.check;
  row["reason"] = verdict.reason;
  return row;
}

Row fit_row(const CaseSpec& c, const ResultsStore& store, const WorkPrecisionSettings& wp) {
  std::vector<double> dts, errors;
  for (int level = 0; level < wp.levels; ++level) {
    const std::string key = ladder_key(c, ladder_dt(wp, level));
    const std::optional<Row> row = store.find(key);
    if (row && (*row)["error"].is_number()) {
      dts.push_back((*row)["dt"].get<double>());
      errors.push_back((*row)["error"].get<double>());
    }
  }
  const analysis::OrderFit fit = analysis::fit_order(dts, errors);
  Row row;
  row["key"] = fit_key(c);
  row["kind"] = "fit";
  for (const auto& [name, value] : c.coordinates) row[name] = value;
  row["fit_valid"] = fit.valid;
  row["order"] = fit.valid ? Row(fit.slope) : Row();
  row["r_squared"] = fit.valid ? Row(fit.r_squared) : Row();
  row["fit_dt_min"] = fit.valid ? Row(fit.dt_min) : Row();
  row["fit_dt_max"] = fit.valid ? Row(fit.dt_max) : Row();
  row["fit_points"] = fit.points;
  row["note"] = fit.note;
  return row;
}

}  // namespace

double relative_rms_error(const std::vector<double>& positions,
                          const std::vector<double>& reference, double diagonal) {
  if (positions.size() != reference.size() || positions.empty() || positions.size() % 3 != 0) {
    throw SweepError("work-precision: " + std::to_string(positions.size()) +
                     " position values against a reference of " + std::to_string(reference.size()));
  }
  if (!(diagonal > 0.0)) {
    throw SweepError("work-precision: cloth diagonal " + host::format_number(diagonal) +
                     ", needs > 0");
  }
  double sum = 0.0;
  for (std::size_t i = 0; i < positions.size(); ++i) {
    const double d = positions[i] - reference[i];
    sum += d * d;
  }
  return std::sqrt(sum / static_cast<double>(positions.size() / 3)) / diagonal;
}

void check_work_precision_cases(const SweepSpec& spec, const std::vector<CaseSpec>& cases) {
  const auto& wp = spec.work_precision;
  const double reference_dt = ladder_dt(wp, wp.levels - 1) / wp.refinement;
  std::vector<std::pair<double, std::string>> step_sizes;
  for (int level = 0; level < wp.levels; ++level)
    step_sizes.emplace_back(ladder_dt(wp, level),
                            "ladder dt (dt_start / 2^" + std::to_string(level) + ")");
  step_sizes.emplace_back(reference_dt, "reference dt (finest ladder dt / refinement)");
  step_sizes.emplace_back(reference_dt / 2.0, "reference dt (finest ladder dt / refinement / 2)");
  for (const CaseSpec& c : cases) {
    const double duration = duration_of(spec, c);
    for (const auto& [dt, name] : step_sizes)
      if (!is_whole_number_of_steps(duration, dt))
        throw SweepError(source_of(spec, c, "duration") + ": duration = " +
                         host::format_number(duration) + " s is not a whole number of steps of " +
                         "the work-precision " + name + " = " + host::format_number(dt) +
                         " s; allowed: a duration that every ladder and reference dt divides (a "
                         "multiple of work_precision.dt_start = " +
                         host::format_number(wp.dt_start) + " s when refinement is whole)");
  }
}

std::size_t work_precision_units(const SweepSpec& spec, const std::vector<CaseSpec>& cases) {
  return cases.size() * static_cast<std::size_t>(spec.work_precision.levels);
}

WorkPrecisionSummary run_work_precision(const SweepSpec& spec, const std::vector<CaseSpec>& cases,
                                        const TrajectoryRunner& runner, ResultsStore& store,
                                        Progress* progress) {
  check_work_precision_cases(spec, cases);
  const auto& wp = spec.work_precision;
  WorkPrecisionSummary summary;
  std::map<std::string, Trajectory> references;  // by reference key, computed on first need
  for (const CaseSpec& c : cases) {
    const double duration = duration_of(spec, c);
    for (int level = 0; level < wp.levels; ++level) {
      const double dt = ladder_dt(wp, level);
      if (store.contains(ladder_key(c, dt))) {
        ++summary.skipped;
        continue;
      }
      auto reference = references.find(reference_key(wp, c));
      if (reference == references.end()) {
        reference =
            references
                .emplace(reference_key(wp, c),
                         compute_reference(spec, c, ladder_dt(wp, wp.levels - 1) / wp.refinement,
                                           runner, store))
                .first;
        ++summary.references;
      }
      const Trajectory run = attempt_trajectory(runner, run_spec(c, dt, duration));
      store.append(ladder_row(c, dt, duration, run, reference->second), c.index);
      ++summary.runs;
      if (progress)
        progress->case_finished(c.integrator + " " + c.key + " dt=" + host::format_number(dt));
    }
    if (!store.contains(fit_key(c))) store.append(fit_row(c, store, wp), c.index);
  }
  if (progress) progress->finish();
  return summary;
}

}  // namespace clothlab::sweep
