#include <algorithm>
#include <cstdio>

#include "integrator_search.hpp"

namespace clothlab::sweep::choice_detail {

namespace {
// How far past a collider's thickness a particle may lie and not count as tunnelling: the
// contacts put it exactly at the thickness, which float32 positions a few metres from the
// origin round by up to ~5e-7 m (with thickness 0, onto either side of the surface).
constexpr double tunnelling_tolerance_m = 1e-6;
}  // namespace

bool timed_out(const Trajectory& run) {
  return run.verdict.status == CaseStatus::Failed &&
         run.verdict.reason.find("timed out") != std::string::npos;
}

// Stage 1, once some setting passed: the first frames at the scene's mesh. A setting is
// stopped there when nothing in the bracket it tops, (failing, value] along the parameter
// searched, can cost within stop_factor / 2 of the best's: it costs at least the setting's
// frames x (failing + 1) / value (see bisect_at), and settings above it cost more. One that
// diverges fails.
bool IntegratorSearch::judge_first_frames(const CaseSpec& c, uint32_t substeps, uint32_t iterations,
                                          uint32_t failing, Probe& probe) {
  if (!context_.best.found() || settings_.stop_factor <= 0) return true;
  const double frames = first_frames();
  // The first frames are measured, not timed: they get the best's whole run as their wall
  // limit, a backstop for a setting whose frames take seconds each.
  const double timeout_s = budget_s(1.0);
  const CaseSpec short_case = first_frames_case(c);
  const Trajectory first = attempt_within(short_case, timeout_s);
  probe.ms_per_frame = first.summary.ms_per_frame.median;
  if (stopped_by_budget(first, timeout_s, "its first frames", probe)) return false;
  // Cost first: over the budget, whether the setting is stable does not matter (more
  // substeps, which might be stable, cost more still). Judged on the fastest frames, and on
  // a second run before a stop: other jobs on the machine only ever slow frames down, and a
  // burst of them can outlast five frames.
  const uint32_t value = candidate_.has_iterations ? iterations : substeps;
  const double floor_fraction = (failing + 1.0) / value;
  const auto limit = [&](double best) { return settings_.stop_factor / 2 * best / floor_fraction; };
  if (first.summary.ms_per_frame.p10 <= limit(context_.best.ms_per_frame))
    return judge_run(first, probe, "in its first frames") &&
           judge_stretch(first, probe, " in its first frames") &&
           judge_penetration(first, probe, " in its first frames");
  const Trajectory again = attempt_within(short_case, timeout_s);
  const double fastest =
      again.verdict.stable() || !timed_out(again)
          ? std::min(first.summary.ms_per_frame.p10, again.summary.ms_per_frame.p10)
          : first.summary.ms_per_frame.p10;
  // And beside the best's first frames measured now: a load that grew since the best was
  // measured slows both alike (the larger of the two is the yardstick).
  const Trajectory best_first = attempt_within(context_.best.first_frames, timeout_s);
  const double best_now = best_first.verdict.stable() ? best_first.summary.ms_per_frame.p10 : 0.0;
  const double yardstick = std::max(context_.best.ms_per_frame, best_now);
  if (fastest <= limit(yardstick))
    return judge_run(first, probe, "in its first frames") &&
           judge_stretch(first, probe, " in its first frames") &&
           judge_penetration(first, probe, " in its first frames");
  char cost[192];
  int length = std::snprintf(
      cost, sizeof cost, "its fastest of %g first frames took %.4g ms (twice)", frames, fastest);
  const uint32_t searched = candidate_.has_iterations ? substeps : 0;
  if (failing + 1 < value)
    std::snprintf(cost + length, sizeof cost - length, ", so %u to %s cost at least %.4g ms/frame",
                  failing + 1, value_label(searched, value).c_str(), fastest * floor_fraction);
  stop(probe,
       cost + (", over " + format_number(settings_.stop_factor / 2) + " x (stop_factor / 2)"),
       best_now > context_.best.ms_per_frame ? best_now : 0.0);
  return false;
}

// Stage 2: the error, on the error mesh to the error T (the cheaper run).
bool IntegratorSearch::judge_error_run(const CaseSpec& c, Probe& probe) {
  if (same_error_run()) return true;
  const double timeout_s = budget_s(error_work_fraction());
  const Trajectory measured = attempt_within(error_case(c), timeout_s);
  if (stopped_by_budget(measured, timeout_s, "its run on the error mesh", probe)) return false;
  const std::string where = settings_.error_mesh.empty()
                                ? "to T = " + format_number(error_duration(settings_)) + " s"
                                : "on the error mesh " + settings_.error_mesh;
  return judge_run(measured, probe, where) && judge_error(measured, probe);
}

// Stage 3: the run over T at the scene's mesh: stability, stretch, cost.
bool IntegratorSearch::judge_full_run(const CaseSpec& c, Probe& probe, double& wall_s) {
  const double timeout_s = budget_s(1.0);
  const Trajectory run = attempt_within(c, timeout_s);
  probe.ms_per_frame = run.summary.ms_per_frame.median;
  if (run.verdict.status != CaseStatus::Failed) probe.run = run.summary;  // a failed run has none
  wall_s = run.summary.wall_time_s;
  if (stopped_by_budget(run, timeout_s, "its run", probe) || !judge_run(run, probe, "") ||
      !judge_stretch(run, probe, "") || !judge_penetration(run, probe, ""))
    return false;
  return !same_error_run() || judge_error(run, probe);
}

// The robust figure: the springs at the pins are left out. The run stops at the check that
// passes the limit (stability.stretch_stop judges the same figure).
bool IntegratorSearch::judge_stretch(const Trajectory& run, Probe& probe,
                                     const std::string& where) const {
  if (!(run.summary.max_stretch_away_from_pins.over_run > settings_.stretch_limit)) return true;
  probe.run = run.summary;
  probe.why = "stretch " + format_number(run.summary.max_stretch_away_from_pins.over_run) +
              " away from the pins above " + format_number(settings_.stretch_limit) + where;
  return false;
}

// A particle deeper inside a collider's surface than that collider's thickness went through the
// band the contacts keep clear: at a larger penetration it tunnels through a thin body part.
bool IntegratorSearch::judge_penetration(const Trajectory& run, Probe& probe,
                                         const std::string& where) const {
  if (!(run.summary.max_depth_past_thickness() > tunnelling_tolerance_m)) return true;
  probe.run = run.summary;
  probe.why = "a particle " + format_number(run.summary.max_depth_past_thickness()) +
              " m past the thickness of a collider (deepest penetration " +
              format_number(run.summary.max_penetration()) + " m)" + where;
  return false;
}

// On the error run, against the reference's own robust stretch over the same run: a method
// whose cloth sags like a softer one (xpbd's m / h^2 stiffness) may match positions at a short
// T and still not be this cloth.
bool IntegratorSearch::judge_stretch_against_reference(const Trajectory& measured,
                                                       Probe& probe) const {
  const double reference = context_.reference.summary.max_stretch_away_from_pins.over_run;
  if (!(reference >= 1.0)) return true;  // a reference without the figure judges nothing
  const double allowed = 1.0 + settings_.reference_stretch_factor * (reference - 1.0);
  if (!(measured.summary.max_stretch_away_from_pins.over_run > allowed)) return true;
  probe.why = "stretch " + format_number(measured.summary.max_stretch_away_from_pins.over_run) +
              " away from the pins" +
              (settings_.error_mesh.empty() ? "" : " on the error mesh " + settings_.error_mesh) +
              ", a strain over " + format_number(settings_.reference_stretch_factor) +
              " x the reference's (" + format_number(reference) + ")";
  return false;
}

// False with probe.why set when the run was not stable; a probe-timeout ends the search.
bool IntegratorSearch::judge_run(const Trajectory& run, Probe& probe, const std::string& where) {
  if (run.verdict.stable()) return true;
  probe.why = (where.empty() ? "" : where + ": ") + to_string(run.verdict.status) + ": " +
              run.verdict.reason;
  if (timed_out(run))
    give_up("too slow: the run at " + current_label_ + (where.empty() ? "" : " " + where) +
            " ran past " + format_number(settings_.probe_timeout_s) + " s (choose.probe_timeout)");
  return false;
}

bool IntegratorSearch::judge_error(const Trajectory& measured, Probe& probe) const {
  probe.error = relative_rms_error(measured.positions, context_.reference.positions,
                                   context_.reference.diagonal);
  if (probe.error <= settings_.error_tolerance)
    return judge_stretch_against_reference(measured, probe);
  probe.error_failed = true;
  const auto [error, tolerance] = percents_apart(probe.error, settings_.error_tolerance);
  probe.why = "error " + error + " above " + tolerance;
  return false;
}

// Early stops when going on cannot help (see the header); returns a note for the progress
// line when it stops something.
std::string IntegratorSearch::judge_progress(uint32_t substeps, uint32_t iterations,
                                             const Probe& probe) {
  if (give_up_ || !probe.error_failed) return "";
  const auto similar = [&](const Probe& other) {
    return other.error_failed && std::abs(probe.error - other.error) < 0.1 * probe.error;
  };
  // Same iterations, two and four times the step: an error that two halvings leave flat is
  // the method's own limit (one halving is not enough: at the coarsest steps the error can
  // saturate at the size of the motion itself).
  const auto coarser = probes_.find({substeps / 2, iterations});
  const auto coarsest = probes_.find({substeps / 4, iterations});
  if (substeps >= 4 && coarser != probes_.end() && coarsest != probes_.end() &&
      similar(coarser->second) && similar(coarsest->second)) {
    give_up("converges elsewhere: error " + percent(probe.error) + " at " +
            label_of(substeps, iterations) + ", " + percent(coarser->second.error) + " and " +
            percent(coarsest->second.error) + " at 2 and 4 x the step");
    return "";
  }
  // Same substeps, half the iterations: the solver has converged, more iterations cannot
  // lower this error; the next substep count may.
  const auto fewer = probes_.find({substeps, iterations / 2});
  if (iterations >= 2 && fewer != probes_.end() && similar(fewer->second)) {
    stop_substeps_ = true;
    return "; more iterations do not lower the error (" + percent(fewer->second.error) + " at " +
           std::to_string(iterations / 2) + "), next substep count";
  }
  return "";
}

}  // namespace clothlab::sweep::choice_detail
