#include "run_report.hpp"

#include <algorithm>
#include <clothlab/core/simd.hpp>
#include <cstdio>
#include <string>
#include <vector>

#include "statistics.hpp"

namespace clothlab::cli {

namespace {

double median_ms(const std::vector<double>& seconds) { return 1e3 * quantile(seconds, 0.5); }

std::string printf_text(const char* format, auto... values) {
  char buffer[512];
  std::snprintf(buffer, sizeof buffer, format, values...);
  return buffer;
}

// Iterations and misses of an iterative integrator; null for the others.
nlohmann::json contacts_json(const std::optional<RunRecord::ContactFigures>& contacts) {
  if (!contacts) return nullptr;
  return {{"colliders", contacts->colliders},
          {"max_penetration_over_run", contacts->max_penetration_over_run},
          {"max_depth_past_thickness_over_run", contacts->max_depth_past_thickness_over_run},
          {"thickness", contacts->thickness},
          {"particles_inside_at_end", contacts->particles_inside_at_end},
          {"crossings_over_run", contacts->crossings_over_run},
          {"drape_coefficient", contacts->drape_coefficient
                                    ? nlohmann::json(*contacts->drape_coefficient)
                                    : nlohmann::json(nullptr)},
          {"work", contacts->work}};
}

nlohmann::json solver_json(const std::optional<SolverTotals>& solver) {
  if (!solver) return nullptr;
  const double steps = static_cast<double>(std::max<uint64_t>(solver->steps, 1));
  return {{"steps", solver->steps},
          {"iterations", solver->iterations},
          {"iterations_per_step",
           {{"mean", static_cast<double>(solver->iterations) / steps},
            {"max", solver->max_iterations}}},
          {"factorizations", solver->factorizations},
          {"non_converged_steps", solver->non_converged_steps},
          {"first_non_converged_step", solver->first_non_converged_step
                                           ? nlohmann::json(*solver->first_non_converged_step)
                                           : nlohmann::json(nullptr)},
          {"max_residual", solver->max_residual}};
}

}  // namespace

RunFigures compute_figures(const RunRecord& record) {
  RunFigures figures;
  figures.sim_time_s = static_cast<double>(record.steps_taken) * record.dt;
  figures.wall_time_s = record.step_total_s;
  figures.ms_median = median_ms(record.step_s);
  figures.ms_p10 = 1e3 * quantile(record.step_s, 0.1);
  figures.ms_p90 = 1e3 * quantile(record.step_s, 0.9);
  // Integration is the part of a step outside the force phases.
  std::vector<double> integrate_s(record.step_s.size());
  for (size_t i = 0; i < integrate_s.size(); ++i)
    integrate_s[i] =
        std::max(0.0, record.step_s[i] - record.internal_forces_s[i] - record.external_forces_s[i]);
  figures.internal_ms = median_ms(record.internal_forces_s);
  figures.external_ms = median_ms(record.external_forces_s);
  figures.integrate_ms = median_ms(integrate_s);
  // A frame is `substeps` consecutive steps; a trailing partial frame is left out.
  std::vector<double> frame_s;
  const size_t substeps = std::max<uint64_t>(1, record.substeps);
  for (size_t first = 0; first + substeps <= record.step_s.size(); first += substeps)
    frame_s.push_back(std::accumulate(
        record.step_s.begin() + static_cast<std::ptrdiff_t>(first),
        record.step_s.begin() + static_cast<std::ptrdiff_t>(first + substeps), 0.0));
  if (!frame_s.empty()) {
    figures.frame_ms_median = median_ms(frame_s);
    figures.frame_ms_p10 = 1e3 * quantile(frame_s, 0.1);
    figures.frame_ms_p90 = 1e3 * quantile(frame_s, 0.9);
    if (figures.frame_ms_median > 0) figures.frames_per_second = 1e3 / figures.frame_ms_median;
  }
  const double internal_s = record.counters.internal_forces_s;
  if (internal_s > 0)
    figures.springs_per_second = static_cast<double>(record.springs.total()) *
                                 static_cast<double>(record.counters.force_evals) / internal_s;
  if (figures.wall_time_s > 0) figures.real_time_factor = figures.sim_time_s / figures.wall_time_s;
  return figures;
}

nlohmann::json summary_json(const RunRecord& record) {
  const RunFigures figures = compute_figures(record);
  const StageCounters& counters = record.counters;
  nlohmann::json json;
  json["integrator"] = record.integrator;
  json["scenario"] = record.scenario;
  json["integrator_library"] = record.integrator_library;
  json["scenario_library"] = record.scenario_library;
  json["precision"] = to_string(record.precision);
  json["rows"] = record.rows;
  json["cols"] = record.cols;
  json["dt"] = record.dt;
  json["frame_rate"] = record.frame_rate;
  json["substeps"] = record.substeps;
  json["material"] =
      record.material.empty() ? nlohmann::json(nullptr) : nlohmann::json(record.material);
  json["steps"] = record.steps_taken;
  json["steps_requested"] = record.steps_requested;
  json["sim_time_s"] = figures.sim_time_s;
  json["wall_time_s"] = figures.wall_time_s;
  json["loop_time_s"] = record.loop_total_s;
  json["ms_per_step"] = {
      {"median", figures.ms_median}, {"p10", figures.ms_p10}, {"p90", figures.ms_p90}};
  json["phase_ms"] = {{"internal_forces", figures.internal_ms},
                      {"external_forces", figures.external_ms},
                      {"integrate", figures.integrate_ms}};
  json["ms_per_frame"] = {{"median", figures.frame_ms_median},
                          {"p10", figures.frame_ms_p10},
                          {"p90", figures.frame_ms_p90}};
  json["frames_per_second"] = figures.frames_per_second;
  json["max_stretch"] = {{"final", record.final_stretch.max},
                         {"over_run", record.max_stretch_over_run}};
  if (record.max_stretch_over_run_time) {
    const Cloth::LongestSpring& spring = record.max_stretch_over_run_spring;
    if (record.rows == 0)  // not a grid: particles by index
      json["max_stretch"]["over_run_at"] = {{"t", *record.max_stretch_over_run_time},
                                            {"particle", spring.first},
                                            {"to_particle", spring.second}};
    else
      json["max_stretch"]["over_run_at"] = {
          {"t", *record.max_stretch_over_run_time},
          {"row", spring.row},
          {"col", spring.col},
          {"to_row", spring.row + spring.row_step},
          {"to_col", static_cast<int64_t>(spring.col) + spring.col_step}};
  }
  json["max_stretch_away_from_pins"] = {{"final", record.final_stretch.max_away_from_pins},
                                        {"over_run", record.max_stretch_away_from_pins_over_run}};
  json["p99_stretch"] = {{"final", record.final_p99_stretch},
                         {"over_run", record.p99_stretch_over_run}};
  json["mean_stretch"] = record.final_stretch.mean;
  json["springs"] = record.springs.total();
  json["force_evals"] = counters.force_evals;
  json["springs_per_second"] = figures.springs_per_second;
  json["real_time_factor"] = figures.real_time_factor;
  json["stable"] = record.stable;
  json["interrupted"] = record.interrupted;
  json["stretch_stopped"] = record.stretch_stopped;
  json["verdict"] = record.verdict;
  json["failed_check"] =
      record.failed_check.empty() ? nlohmann::json(nullptr) : nlohmann::json(record.failed_check);
  json["failed_step"] =
      record.failed_step ? nlohmann::json(*record.failed_step) : nlohmann::json(nullptr);
  json["stability_checks"] = record.stability_checks;
  json["solver"] = solver_json(record.solver);
  json["contacts"] = contacts_json(record.contacts);
  json["attachments"] = record.attachments
                            ? nlohmann::json{{"particles", record.attachments->particles},
                                             {"work", record.attachments->work}}
                            : nlohmann::json(nullptr);
  json["threads"] = record.threads;
  json["simd"] = std::string(simd_target());
  json["counters"] = {{"springs_evaluated", counters.springs_evaluated},
                      {"springs_damped", counters.springs_damped},
                      {"normals_computed", counters.normals_computed},
                      {"particles_integrated", counters.particles_integrated},
                      {"steps_on_one_thread", counters.steps_on_one_thread}};
  json["integrator_params"] = record.integrator_params;
  json["scenario_params"] = record.scenario_params;
  return json;
}

std::string human_summary(const RunRecord& record) {
  const RunFigures figures = compute_figures(record);
  std::string text = printf_text(
      "%s on %s, %ux%u, %s, %d threads, SIMD %s: %llu steps of %g s = %g s simulated\n",
      record.integrator.c_str(), record.scenario.c_str(), record.rows, record.cols,
      to_string(record.precision), record.threads, std::string(simd_target()).c_str(),
      static_cast<unsigned long long>(record.steps_taken), record.dt, figures.sim_time_s);
  text += printf_text(
      "  %.4g ms/step (median; p10 %.4g, p90 %.4g), stepping wall time %.4g s, real-time "
      "factor %.3g\n",
      figures.ms_median, figures.ms_p10, figures.ms_p90, figures.wall_time_s,
      figures.real_time_factor);
  text += printf_text(
      "  frames: %g Hz x %llu substeps: %.4g ms/frame (median), %.4g frames/s achievable\n",
      record.frame_rate, static_cast<unsigned long long>(record.substeps), figures.frame_ms_median,
      figures.frames_per_second);
  std::string where;
  if (record.max_stretch_over_run_time) {
    const Cloth::LongestSpring& spring = record.max_stretch_over_run_spring;
    where = record.rows == 0
                ? printf_text(" at t = %.4g s, spring %u-%u", *record.max_stretch_over_run_time,
                              spring.first, spring.second)
                : printf_text(" at t = %.4g s, spring (%u, %u)-(%u, %lld)",
                              *record.max_stretch_over_run_time, spring.row, spring.col,
                              spring.row + spring.row_step,
                              static_cast<long long>(spring.col) + spring.col_step);
  }
  text += printf_text("  stretch: max %.4g (final), %.4g (over the run%s), mean %.4g%s%s\n",
                      record.final_stretch.max, record.max_stretch_over_run, where.c_str(),
                      record.final_stretch.mean, record.material.empty() ? "" : "; material ",
                      record.material.c_str());
  text += printf_text(
      "  robust stretch over the run: 99th percentile %.4g, max away from the pins %.4g\n",
      record.p99_stretch_over_run, record.max_stretch_away_from_pins_over_run);
  text += printf_text(
      "  per step: internal forces %.4g ms, external forces %.4g ms, integrate %.4g ms; "
      "%.3g springs/s\n",
      figures.internal_ms, figures.external_ms, figures.integrate_ms, figures.springs_per_second);
  if (record.solver)
    text += printf_text(
        "  solver: %.4g iterations/step (max %llu), %llu factorisations, %llu steps missed "
        "the tolerance\n",
        static_cast<double>(record.solver->iterations) /
            static_cast<double>(std::max<uint64_t>(record.solver->steps, 1)),
        static_cast<unsigned long long>(record.solver->max_iterations),
        static_cast<unsigned long long>(record.solver->factorizations),
        static_cast<unsigned long long>(record.solver->non_converged_steps));
  if (record.contacts)
    text += printf_text(
        "  contacts: %zu collider(s), max penetration %.3g m over the run, %llu crossings, %u "
        "particles inside at the end, drape coefficient %s\n",
        record.contacts->colliders, record.contacts->max_penetration_over_run,
        static_cast<unsigned long long>(record.contacts->crossings_over_run),
        static_cast<unsigned>(record.contacts->particles_inside_at_end),
        record.contacts->drape_coefficient
            ? printf_text("%.3f", *record.contacts->drape_coefficient).c_str()
            : "none (no gravity)");
  text += "  verdict: " + record.verdict + "\n";
  return text;
}

void write_energy_csv(const RunRecord& record, std::ostream& out) {
  out << "integrator,t,kinetic,spring,gravity,total\n";
  for (const RunRecord::EnergySample& sample : record.energy_trace)
    out << record.integrator
        << printf_text(",%.17g,%.17g,%.17g,%.17g,%.17g\n", sample.t, sample.energy.kinetic,
                       sample.energy.spring, sample.energy.gravity, sample.energy.total());
}

void write_state_csv(const Cloth& cloth, std::ostream& out) {
  std::vector<double> x, v;
  cloth.positions(x);
  cloth.velocities(v);
  const uint32_t cols = cloth.scene().cols;  // 0: not a grid, particles by index
  out << (cols == 0 ? "particle,x,y,z,vx,vy,vz\n" : "row,col,x,y,z,vx,vy,vz\n");
  for (uint32_t i = 0; i < cloth.particle_count(); ++i) {
    const size_t k = 3 * static_cast<size_t>(i);
    const std::string where =
        cols == 0 ? printf_text("%u", i) : printf_text("%u,%u", i / cols, i % cols);
    out << where
        << printf_text(",%.17g,%.17g,%.17g,%.17g,%.17g,%.17g\n", x[k], x[k + 1], x[k + 2], v[k],
                       v[k + 1], v[k + 2]);
  }
}

}  // namespace clothlab::cli
