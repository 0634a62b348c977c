#include "run_report.hpp"

#include <algorithm>
#include <cstdio>
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
  json["steps"] = record.steps_taken;
  json["steps_requested"] = record.steps_requested;
  json["sim_time_s"] = figures.sim_time_s;
  json["wall_time_s"] = figures.wall_time_s;
  json["ms_per_step"] = {
      {"median", figures.ms_median}, {"p10", figures.ms_p10}, {"p90", figures.ms_p90}};
  json["phase_ms"] = {{"internal_forces", figures.internal_ms},
                      {"external_forces", figures.external_ms},
                      {"integrate", figures.integrate_ms}};
  json["springs"] = record.springs.total();
  json["force_evals"] = counters.force_evals;
  json["springs_per_second"] = figures.springs_per_second;
  json["real_time_factor"] = figures.real_time_factor;
  json["stable"] = record.stable;
  json["verdict"] = record.verdict;
  json["failed_check"] =
      record.failed_check.empty() ? nlohmann::json(nullptr) : nlohmann::json(record.failed_check);
  json["failed_step"] =
      record.failed_step ? nlohmann::json(*record.failed_step) : nlohmann::json(nullptr);
  json["stability_checks"] = record.stability_checks;
  json["threads"] = record.threads;
  json["counters"] = {{"springs_evaluated", counters.springs_evaluated},
                      {"springs_damped", counters.springs_damped},
                      {"normals_computed", counters.normals_computed},
                      {"particles_integrated", counters.particles_integrated}};
  json["integrator_params"] = record.integrator_params;
  json["scenario_params"] = record.scenario_params;
  return json;
}

std::string human_summary(const RunRecord& record) {
  const RunFigures figures = compute_figures(record);
  std::string text = printf_text(
      "%s on %s, %ux%u, %s, %d threads: %llu steps of %g s = %g s simulated\n",
      record.integrator.c_str(), record.scenario.c_str(), record.rows, record.cols,
      to_string(record.precision), record.threads,
      static_cast<unsigned long long>(record.steps_taken), record.dt, figures.sim_time_s);
  text += printf_text(
      "  %.4g ms/step (median; p10 %.4g, p90 %.4g), stepping wall time %.4g s, real-time "
      "factor %.3g\n",
      figures.ms_median, figures.ms_p10, figures.ms_p90, figures.wall_time_s,
      figures.real_time_factor);
  text += printf_text(
      "  per step: internal forces %.4g ms, external forces %.4g ms, integrate %.4g ms; "
      "%.3g springs/s\n",
      figures.internal_ms, figures.external_ms, figures.integrate_ms, figures.springs_per_second);
  text += "  verdict: " + record.verdict + "\n";
  return text;
}

void write_state_csv(const Cloth& cloth, std::ostream& out) {
  std::vector<double> x, v;
  cloth.positions(x);
  cloth.velocities(v);
  const uint32_t cols = cloth.scene().cols;
  out << "row,col,x,y,z,vx,vy,vz\n";
  for (uint32_t i = 0; i < cloth.particle_count(); ++i) {
    const size_t k = 3 * static_cast<size_t>(i);
    out << printf_text("%u,%u,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g\n", i / cols, i % cols, x[k],
                       x[k + 1], x[k + 2], v[k], v[k + 1], v[k + 2]);
  }
}

}  // namespace clothlab::cli
