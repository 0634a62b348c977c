#include <algorithm>
#include <cstdio>

#include "integrator_search.hpp"

namespace clothlab::sweep::choice_detail {

namespace {

// A child process needs this long beyond its stepping (start, plugins, scene, the JSON with
// the final positions); the cost budget allows it on top of its multiple of the best's time.
constexpr double startup_allowance_s = 1.0;
// Frames of the first, short run that measures a setting's cost: the median of 5 leaves out
// a first frame that sets up (a factorisation, page faults).
constexpr int cost_frames = 5;

}  // namespace

// Where to bisect (failing, passing] next: its middle, or lower where another integrator's
// best is cheaper than the upper part of the bracket can be, none where it is cheaper than
// all of it. A frame's cost per substep (per iteration) does not grow with their number
// (cost = a + b n, a >= 0), so n costs at least cost(passing) n / passing: the bracket can
// beat the best only up to n = best passing / cost(passing), its cut.
std::optional<uint32_t> IntegratorSearch::bisect_at(uint32_t substeps, uint32_t failing,
                                                    uint32_t passing) {
  const uint32_t middle = failing + (passing - failing) / 2;
  const BestSoFar& best = context_.best;
  if (!best.found() || best.integrator == candidate_.integrator || settings_.stop_factor <= 0)
    return middle;
  double cost = probes_.at(key(substeps, passing)).ms_per_frame;
  double cut = best.ms_per_frame * passing / cost;
  std::string yardstick = best.label;
  if (cut < middle) {
    // The two costs were measured at different times: measured again side by side (their
    // first frames, the fastest of them), the larger cut stands, so that a load that grew
    // in between cuts nothing.
    const auto [s, it] = key(substeps, passing);
    const double timeout_s = budget_s(1.0);
    const Trajectory mine = attempt_within(first_frames_case(candidate_case(s, it)), timeout_s);
    const Trajectory theirs = attempt_within(best.first_frames, timeout_s);
    if (mine.verdict.stable() && theirs.verdict.stable() && mine.summary.ms_per_frame.p10 > 0 &&
        theirs.summary.ms_per_frame.p10 * passing / mine.summary.ms_per_frame.p10 > cut) {
      cut = theirs.summary.ms_per_frame.p10 * passing / mine.summary.ms_per_frame.p10;
      cost = mine.summary.ms_per_frame.p10;
      char now[64];
      std::snprintf(now, sizeof now, " (%.4g ms its first frames now)",
                    theirs.summary.ms_per_frame.p10);
      yardstick += now;
    }
  }
  if (cut >= middle) return middle;
  if (cut >= failing + 1) return static_cast<uint32_t>(cut);
  char text[96];
  std::snprintf(text, sizeof text, ": %u or more cost at least %.4g ms/frame, more than ",
                failing + 1, cost * (failing + 1) / passing);
  unrefined_[key(substeps, passing)] =
      "not refined below " + value_label(substeps, passing) + text + yardstick;
  return std::nullopt;
}

// An upper bound on the error run's share of the work of the run over T at the scene's
// mesh: its share of T. (A step on a smaller mesh costs less, but not in proportion to the
// particles: per-step overheads stay.)
double IntegratorSearch::error_work_fraction() const {
  return error_duration(settings_) / settings_.duration;
}

// The wall-clock limit of a run doing `work_fraction` of a full probe's work: the probe
// timeout, or, once some setting passed, 2 x stop_factor x the best's time (see the header).
// Twice the factor of the cost check: a wall time carries every stall other jobs cause.
double IntegratorSearch::budget_s(double work_fraction) const {
  const BestSoFar& best = context_.best;
  if (!best.found() || settings_.stop_factor <= 0) return settings_.probe_timeout_s;
  return std::min(settings_.probe_timeout_s,
                  startup_allowance_s + 2 * settings_.stop_factor * best.wall_s * work_fraction);
}

// A run killed by the cost budget (not by the probe timeout) marks the probe stopped.
bool IntegratorSearch::stopped_by_budget(const Trajectory& run, double timeout_s,
                                         const std::string& where, Probe& probe) const {
  if (!timed_out(run) || timeout_s >= settings_.probe_timeout_s) return false;
  stop(probe, where + " ran past " + format_number(timeout_s) + " s, over " +
                  format_number(settings_.stop_factor) + " x");
  return true;
}

// `best_now`: the best's first frames (p10) measured beside the probe, where that raised
// the yardstick; 0: its ms/frame was the yardstick.
void IntegratorSearch::stop(Probe& probe, const std::string& why, double best_now) const {
  char best[96];
  int length = std::snprintf(best, sizeof best, " (%.4g ms/frame", context_.best.ms_per_frame);
  if (best_now > 0)
    std::snprintf(best + length, sizeof best - length, "; %.4g ms its first frames now", best_now);
  probe.stopped = true;
  probe.why = "slower than " + context_.best.label + best + "): " + why;
}

CaseSpec IntegratorSearch::first_frames_case(const CaseSpec& c) const {
  return with_setting(c, "duration", format_number(first_frames() / settings_.frame_rate), false);
}

double IntegratorSearch::first_frames() const {
  return std::min<double>(cost_frames, settings_.duration * settings_.frame_rate);
}

void IntegratorSearch::record_best(uint32_t substeps, uint32_t iterations, const CaseSpec& c,
                                   const Probe& probe, double wall_s) {
  BestSoFar& best = context_.best;
  if (probe.ms_per_frame >= best.ms_per_frame) return;
  best.integrator = candidate_.integrator;
  best.label = candidate_.integrator + " at " + label_of(substeps, iterations);
  best.ms_per_frame = probe.ms_per_frame;
  best.wall_s = wall_s;
  best.first_frames = first_frames_case(c);
}

}  // namespace clothlab::sweep::choice_detail
