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

host::RunSummary::Spread spread_ms(const std::vector<double>& seconds) {
  return {median_ms(seconds), 1e3 * quantile(seconds, 0.1), 1e3 * quantile(seconds, 0.9)};
}

std::string printf_text(const char* format, auto... values) {
  char buffer[512];
  std::snprintf(buffer, sizeof buffer, format, values...);
  return buffer;
}

}  // namespace

host::RunSummary summarize(const RunRecord& record) {
  host::RunSummary summary;
  summary.integrator = record.integrator;
  summary.scenario = record.scenario;
  summary.integrator_library = record.integrator_library;
  summary.scenario_library = record.scenario_library;
  summary.precision = to_string(record.precision);
  summary.rows = record.rows;
  summary.cols = record.cols;
  summary.dt = record.dt;
  summary.frame_rate = record.frame_rate;
  summary.substeps = record.substeps;
  if (!record.material.empty()) summary.material = record.material;
  summary.steps = record.steps_taken;
  summary.steps_requested = record.steps_requested;
  summary.sim_time_s = static_cast<double>(record.steps_taken) * record.dt;
  summary.wall_time_s = record.step_total_s;
  summary.loop_time_s = record.loop_total_s;
  summary.ms_per_step = spread_ms(record.step_s);
  // Integration is the part of a step outside the force phases.
  std::vector<double> integrate_s(record.step_s.size());
  for (size_t i = 0; i < integrate_s.size(); ++i)
    integrate_s[i] =
        std::max(0.0, record.step_s[i] - record.internal_forces_s[i] - record.external_forces_s[i]);
  summary.phase_ms = {median_ms(record.internal_forces_s), median_ms(record.external_forces_s),
                      median_ms(integrate_s)};
  // A frame is `substeps` consecutive steps; a trailing partial frame is left out.
  std::vector<double> frame_s;
  const size_t substeps = std::max<uint64_t>(1, record.substeps);
  for (size_t first = 0; first + substeps <= record.step_s.size(); first += substeps)
    frame_s.push_back(std::accumulate(
        record.step_s.begin() + static_cast<std::ptrdiff_t>(first),
        record.step_s.begin() + static_cast<std::ptrdiff_t>(first + substeps), 0.0));
  if (!frame_s.empty()) {
    summary.ms_per_frame = spread_ms(frame_s);
    if (summary.ms_per_frame.median > 0)
      summary.frames_per_second = 1e3 / summary.ms_per_frame.median;
  }
  summary.max_stretch.final = record.final_stretch.max;
  summary.max_stretch.over_run = record.max_stretch_over_run;
  if (record.max_stretch_over_run_time) {
    const Cloth::LongestSpring& spring = record.max_stretch_over_run_spring;
    host::RunSummary::SpringSeen& seen = summary.max_stretch.over_run_at.emplace();
    seen.t = *record.max_stretch_over_run_time;
    if (record.rows == 0) {  // not a grid: particles by index
      seen.particle = spring.first;
      seen.to_particle = spring.second;
    } else {
      seen.row = spring.row;
      seen.col = spring.col;
      seen.to_row = spring.row + spring.row_step;
      seen.to_col = static_cast<int64_t>(spring.col) + spring.col_step;
    }
  }
  summary.max_stretch_away_from_pins = {record.final_stretch.max_away_from_pins,
                                        record.max_stretch_away_from_pins_over_run};
  summary.p99_stretch = {record.final_p99_stretch, record.p99_stretch_over_run};
  summary.mean_stretch = record.final_stretch.mean;
  const StageCounters& counters = record.counters;
  summary.springs = record.springs.total();
  summary.force_evals = counters.force_evals;
  if (counters.internal_forces_s > 0)
    summary.springs_per_second = static_cast<double>(record.springs.total()) *
                                 static_cast<double>(counters.force_evals) /
                                 counters.internal_forces_s;
  if (summary.wall_time_s > 0) summary.real_time_factor = summary.sim_time_s / summary.wall_time_s;
  summary.stable = record.stable;
  summary.interrupted = record.interrupted;
  summary.stretch_stopped = record.stretch_stopped;
  summary.verdict = record.verdict;
  if (!record.failed_check.empty()) summary.failed_check = record.failed_check;
  summary.failed_step = record.failed_step;
  summary.stability_checks = record.stability_checks;
  if (const std::optional<SolverTotals>& solver = record.solver) {
    const double steps = static_cast<double>(std::max<uint64_t>(solver->steps, 1));
    summary.solver = host::RunSummary::Solver{
        solver->steps,
        solver->iterations,
        {static_cast<double>(solver->iterations) / steps, solver->max_iterations},
        solver->factorizations,
        solver->non_converged_steps,
        solver->first_non_converged_step,
        solver->max_residual};
  }
  if (const std::optional<RunRecord::ContactFigures>& contacts = record.contacts)
    summary.contacts = host::RunSummary::Contacts{contacts->colliders,
                                                  contacts->max_penetration_over_run,
                                                  contacts->max_depth_past_thickness_over_run,
                                                  contacts->thickness,
                                                  contacts->particles_inside_at_end,
                                                  contacts->crossings_over_run,
                                                  contacts->drape_coefficient,
                                                  contacts->work};
  if (record.attachments)
    summary.attachments =
        host::RunSummary::Attachments{record.attachments->particles, record.attachments->work};
  summary.threads = record.threads;
  summary.simd = std::string(simd_target());
  summary.counters = {counters.springs_evaluated, counters.springs_damped,
                      counters.normals_computed, counters.particles_integrated,
                      counters.steps_on_one_thread};
  summary.integrator_params = record.integrator_params;
  summary.scenario_params = record.scenario_params;
  return summary;
}

nlohmann::json summary_json(const RunRecord& record) { return host::to_json(summarize(record)); }

std::string human_summary(const host::RunSummary& run) {
  std::string text = printf_text(
      "%s on %s, %llux%llu, %s, %lld threads, SIMD %s: %llu steps of %g s = %g s simulated\n",
      run.integrator.c_str(), run.scenario.c_str(), static_cast<unsigned long long>(run.rows),
      static_cast<unsigned long long>(run.cols), run.precision.c_str(),
      static_cast<long long>(run.threads), run.simd.c_str(),
      static_cast<unsigned long long>(run.steps), run.dt, run.sim_time_s);
  text += printf_text(
      "  %.4g ms/step (median; p10 %.4g, p90 %.4g), stepping wall time %.4g s, real-time "
      "factor %.3g\n",
      run.ms_per_step.median, run.ms_per_step.p10, run.ms_per_step.p90, run.wall_time_s,
      run.real_time_factor);
  text += printf_text(
      "  frames: %g Hz x %llu substeps: %.4g ms/frame (median), %.4g frames/s achievable\n",
      run.frame_rate, static_cast<unsigned long long>(run.substeps), run.ms_per_frame.median,
      run.frames_per_second);
  std::string where;
  if (const std::optional<host::RunSummary::SpringSeen>& seen = run.max_stretch.over_run_at) {
    where = seen->particle ? printf_text(" at t = %.4g s, spring %llu-%llu", seen->t,
                                         static_cast<unsigned long long>(*seen->particle),
                                         static_cast<unsigned long long>(*seen->to_particle))
                           : printf_text(" at t = %.4g s, spring (%llu, %llu)-(%llu, %lld)",
                                         seen->t, static_cast<unsigned long long>(*seen->row),
                                         static_cast<unsigned long long>(*seen->col),
                                         static_cast<unsigned long long>(*seen->to_row),
                                         static_cast<long long>(*seen->to_col));
  }
  text +=
      printf_text("  stretch: max %.4g (final), %.4g (over the run%s), mean %.4g%s%s\n",
                  run.max_stretch.final, run.max_stretch.over_run, where.c_str(), run.mean_stretch,
                  run.material ? "; material " : "", run.material.value_or("").c_str());
  text += printf_text(
      "  robust stretch over the run: 99th percentile %.4g, max away from the pins %.4g\n",
      run.p99_stretch.over_run, run.max_stretch_away_from_pins.over_run);
  text += printf_text(
      "  per step: internal forces %.4g ms, external forces %.4g ms, integrate %.4g ms; "
      "%.3g springs/s\n",
      run.phase_ms.internal_forces, run.phase_ms.external_forces, run.phase_ms.integrate,
      run.springs_per_second);
  if (run.solver)
    text += printf_text(
        "  solver: %.4g iterations/step (max %llu), %llu factorisations, %llu steps missed "
        "the tolerance\n",
        run.solver->iterations_per_step.mean,
        static_cast<unsigned long long>(run.solver->iterations_per_step.max),
        static_cast<unsigned long long>(run.solver->factorizations),
        static_cast<unsigned long long>(run.solver->non_converged_steps));
  if (run.contacts)
    text += printf_text(
        "  contacts: %llu collider(s), max penetration %.3g m over the run, %llu crossings, %llu "
        "particles inside at the end, drape coefficient %s\n",
        static_cast<unsigned long long>(run.contacts->colliders),
        run.contacts->max_penetration_over_run,
        static_cast<unsigned long long>(run.contacts->crossings_over_run),
        static_cast<unsigned long long>(run.contacts->particles_inside_at_end),
        run.contacts->drape_coefficient
            ? printf_text("%.3f", *run.contacts->drape_coefficient).c_str()
            : "none (no gravity)");
  text += "  verdict: " + run.verdict + "\n";
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
