#include "clothlab/sweep/integrator_choice.hpp"

#include <chrono>
#include <clothlab/analysis/bracket_search.hpp>
#include <clothlab/host/param_text.hpp>
#include <cmath>
#include <cstdio>
#include <functional>
#include <map>
#include <optional>

#include "clothlab/sweep/case_attempt.hpp"
#include "clothlab/sweep/progress.hpp"
#include "clothlab/sweep/sweep_error.hpp"

namespace clothlab::sweep {
namespace {

using host::format_number;

struct Probe {
  bool passed = false;
  bool error_failed = false;  // failed on the error criterion (the other runs were fine)
  bool stopped = false;       // killed by the cost budget: slower than the best verdict so far
  double ms_per_frame = 0, error = NAN, max_stretch = NAN;
  std::string why;  // the failed criterion; empty when passed
};

// The cheapest passing probe of any integrator so far: the yardstick of the cost budget.
struct BestSoFar {
  std::string integrator;
  std::string label;  // "verlet at 1536 substeps"
  double ms_per_frame = INFINITY;
  double wall_s = 0;      // stepping wall time of its run over T at the scene's mesh
  CaseSpec first_frames;  // its first frames' run, measured again beside a setting to be stopped
  bool found() const { return std::isfinite(ms_per_frame); }
};

// What every integrator's search shares: the scene, the reference, the budget's yardstick.
struct SearchContext {
  const ChoiceSettings& settings;
  const TrajectoryRunner& runner;
  const Trajectory& reference;
  ResultsStore& store;
  std::ostream& progress;
  std::chrono::steady_clock::time_point start;
  BestSoFar best;
};

// A child process needs this long beyond its stepping (start, plugins, scene, the JSON with
// the final positions); the cost budget allows it on top of its multiple of the best's time.
constexpr double startup_allowance_s = 1.0;
// Frames of the first, short run that measures a setting's cost: the median of 5 leaves out
// a first frame that sets up (a factorisation, page faults).
constexpr int cost_frames = 5;

// A search along one parameter: the fewest passing value found (none: nothing passed, or the
// cost budget stopped the doubling), and the value whose stop ended the bisection, if one did.
struct Fewest {
  std::optional<uint32_t> passing;
  uint32_t stopped_refining_at = 0;
};

// The fewest n in [1, max] with passes(n), assuming passes is monotone: a bracket search from 1
// (failing values lie below the fewest passing one, analysis::Side::below), doubling, then
// bisection until the bracket is within 10 % (each probe is a full run, so not to the unit).
// probe(n, failing) gets the largest value known to fail below n (0: none), the bottom of the
// bracket n tops. `stop` ends the doubling early (nothing found); `next(failing, passing)`
// names the value to bisect at (the middle, or lower), none to end the bisection.
Fewest fewest(uint32_t max, const std::function<analysis::Side(uint32_t, uint32_t)>& probe,
              const std::function<bool()>& stop,
              const std::function<std::optional<uint32_t>(uint32_t, uint32_t)>& next) {
  const analysis::BracketResult search = analysis::bracket_search(
      [&](double n, double failing) {
        return probe(static_cast<uint32_t>(n), static_cast<uint32_t>(failing));
      },
      {.start = 1,
       .lower_limit = 1,
       .upper_limit = static_cast<double>(std::max(max, 1u)),  // 1 is probed whatever max is
       .relative_tolerance = 0.1,
       .resolution = 1,
       .keep_bracketing = [&] { return !stop(); },
       .bisect_at = [&](double failing, double passing) -> std::optional<double> {
         const std::optional<uint32_t> at =
             next(static_cast<uint32_t>(failing), static_cast<uint32_t>(passing));
         if (!at) return std::nullopt;
         return *at;
       }});
  // A stop before any value passed ends the search with nothing; after, it ends the bisection:
  // nothing in (failing, stopped] is within the budget, and (stopped, passing) costs more.
  if (search.high == 0) return {};
  return {static_cast<uint32_t>(search.high), static_cast<uint32_t>(search.stopped_at)};
}

std::string percent(double fraction) {
  char text[32];
  std::snprintf(text, sizeof text, "%.3g %%", 100 * fraction);
  return text;
}

std::string label_of(uint32_t substeps, uint32_t iterations) {
  return std::to_string(substeps) + (substeps == 1 ? " substep" : " substeps") +
         (iterations ? " x " + std::to_string(iterations) +
                           (iterations == 1 ? " iteration" : " iterations")
                     : "");
}

double error_duration(const ChoiceSettings& settings) {
  return settings.error_duration > 0 ? settings.error_duration : settings.duration;
}

bool timed_out(const Trajectory& run) {
  return run.verdict.status == CaseStatus::Failed &&
         run.verdict.reason.find("timed out") != std::string::npos;
}

class IntegratorSearch {
 public:
  IntegratorSearch(const CaseSpec& base, const ChoiceCandidate& candidate, std::string position,
                   SearchContext& context)
      : base_(with_setting(base, "integrator.plugin", candidate.integrator)),
        candidate_(candidate),
        position_(std::move(position)),
        context_(context),
        settings_(context.settings) {}

  Choice run() {
    Choice choice;
    choice.integrator = candidate_.integrator;
    std::optional<std::pair<uint32_t, uint32_t>> best;  // (substeps, iterations)
    const auto stop = [&] { return give_up_ || stop_substeps_; };
    if (!candidate_.has_iterations) {
      const Fewest substeps = fewest(
          settings_.max_substeps,
          [&](uint32_t s, uint32_t failing) { return side(probe(s, 0, failing)); }, stop,
          [&](uint32_t failing, uint32_t passing) { return bisect_at(0, failing, passing); });
      if (substeps.passing) best = {{*substeps.passing, 0}};
      note_stopped_refining(0, substeps);
    } else {
      // Cost ~ substeps x iterations: walk the substeps up while the cheapest passing
      // iteration count keeps lowering the cost per frame.
      for (uint32_t substeps = 1; substeps <= settings_.max_substeps; substeps *= 2) {
        stop_substeps_ = false;
        stopped_iterations_ = 0;
        const Fewest iterations = fewest(
            max_iterations(),
            [&](uint32_t it, uint32_t failing) { return side(probe(substeps, it, failing)); }, stop,
            [&](uint32_t failing, uint32_t passing) {
              return bisect_at(substeps, failing, passing);
            });
        note_stopped_refining(substeps, iterations);
        if (give_up_) break;
        // Over the budget at one iteration: more substeps only cost more.
        if (stopped_iterations_ == 1) break;
        if (!iterations.passing) continue;
        const double cost = probes_.at({substeps, *iterations.passing}).ms_per_frame;
        if (best && cost >= probes_.at(*best).ms_per_frame) break;
        best = {{substeps, *iterations.passing}};
        if (*iterations.passing == 1) break;  // more substeps only cost more
      }
    }
    choice.probes = static_cast<int>(probes_.size());
    if (!best && !give_up_reason_.empty()) {
      choice.verdict = give_up_reason_;
      return choice;
    }
    if (!best && !stopped_label_.empty()) {
      choice.verdict = stopped_reason_ + "; stopped at " + stopped_label_;
      return choice;
    }
    if (!best) {
      choice.verdict =
          "no setting passed up to " + std::to_string(settings_.max_substeps) + " substeps" +
          (candidate_.has_iterations ? " x " + std::to_string(max_iterations()) + " iterations"
                                     : std::string()) +
          "; last: " + last_failure_;
      return choice;
    }
    const Probe& chosen = probes_.at(*best);
    choice.passed = true;
    choice.substeps = best->first;
    choice.iterations = best->second;
    choice.iterations_param = candidate_.iterations_param;
    choice.ms_per_frame = chosen.ms_per_frame;
    choice.error = chosen.error;
    choice.max_stretch = chosen.max_stretch;
    choice.verdict =
        chosen.ms_per_frame <= 1e3 / settings_.frame_rate ? "real time" : "slower than real time";
    if (const auto note = unrefined_.find(*best); note != unrefined_.end())
      choice.verdict += "; " + note->second;
    return choice;
  }

 private:
  // The search along substeps (substeps 0: the value is the substeps) or along the
  // iterations at `substeps`: its probes' keys and the value's label.
  std::pair<uint32_t, uint32_t> key(uint32_t substeps, uint32_t value) const {
    return substeps ? std::make_pair(substeps, value) : std::make_pair(value, 0u);
  }
  std::string value_label(uint32_t substeps, uint32_t value) const {
    return substeps ? std::to_string(value) + (value == 1 ? " iteration at " : " iterations at ") +
                          label_of(substeps, 0)
                    : label_of(value, 0);
  }

  // Where to bisect (failing, passing] next: its middle, or lower where another integrator's
  // best is cheaper than the upper part of the bracket can be, none where it is cheaper than
  // all of it. A frame's cost per substep (per iteration) does not grow with their number
  // (cost = a + b n, a >= 0), so n costs at least cost(passing) n / passing: the bracket can
  // beat the best only up to n = best passing / cost(passing), its cut.
  std::optional<uint32_t> bisect_at(uint32_t substeps, uint32_t failing, uint32_t passing) {
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
      if (mine.verdict.stable() && theirs.verdict.stable() && mine.ms_per_frame_p10 > 0 &&
          theirs.ms_per_frame_p10 * passing / mine.ms_per_frame_p10 > cut) {
        cut = theirs.ms_per_frame_p10 * passing / mine.ms_per_frame_p10;
        cost = mine.ms_per_frame_p10;
        char now[64];
        std::snprintf(now, sizeof now, " (%.4g ms its first frames now)", theirs.ms_per_frame_p10);
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

  // A bisection ended by the budget: its passing end stays, said so.
  void note_stopped_refining(uint32_t substeps, const Fewest& found) {
    if (!found.passing || !found.stopped_refining_at) return;
    unrefined_[key(substeps, *found.passing)] =
        "not refined below " + value_label(substeps, *found.passing) + ": " +
        value_label(substeps, found.stopped_refining_at) + " " +
        probes_.at(key(substeps, found.stopped_refining_at)).why;
  }

  // A passing setting lies above the failing ones along the parameter searched.
  static analysis::Side side(const Probe& probe) {
    return probe.passed    ? analysis::Side::above
           : probe.stopped ? analysis::Side::stop
                           : analysis::Side::below;
  }

  uint32_t max_iterations() const {
    return std::min(settings_.max_iterations, candidate_.iterations_limit);
  }

  CaseSpec candidate_case(uint32_t substeps, uint32_t iterations) const {
    CaseSpec c = with_setting(base_, "frame_rate", format_number(settings_.frame_rate), false);
    // The stretch over the run only grows: a run at the scene's mesh ends as soon as it
    // passes the limit (the error runs judge no stretch and use error_case).
    c = with_setting(c, "stability.stretch_stop", format_number(settings_.stretch_limit), false);
    c = with_setting(c, "substeps", std::to_string(substeps));
    if (candidate_.has_own_substeps)
      c = with_setting(c, "integrator." + candidate_.substeps_param, "1", false);
    if (iterations > 0)
      c = with_setting(c, "integrator." + candidate_.iterations_param, std::to_string(iterations));
    return c;
  }

  bool same_error_run() const {
    return settings_.error_mesh.empty() && error_duration(settings_) == settings_.duration;
  }
  CaseSpec error_case(const CaseSpec& c) const {
    CaseSpec e = with_setting(c, "duration", format_number(error_duration(settings_)), false);
    e = with_setting(e, "stability.stretch_stop", "0", false);
    return settings_.error_mesh.empty() ? e : with_setting(e, "mesh", settings_.error_mesh);
  }
  // An upper bound on the error run's share of the work of the run over T at the scene's
  // mesh: its share of T. (A step on a smaller mesh costs less, but not in proportion to the
  // particles: per-step overheads stay.)
  double error_work_fraction() const { return error_duration(settings_) / settings_.duration; }

  // The wall-clock limit of a run doing `work_fraction` of a full probe's work: the probe
  // timeout, or, once some setting passed, 2 x stop_factor x the best's time (see the header).
  // Twice the factor of the cost check: a wall time carries every stall other jobs cause.
  double budget_s(double work_fraction) const {
    const BestSoFar& best = context_.best;
    if (!best.found() || settings_.stop_factor <= 0) return settings_.probe_timeout_s;
    return std::min(settings_.probe_timeout_s,
                    startup_allowance_s + 2 * settings_.stop_factor * best.wall_s * work_fraction);
  }

  Trajectory attempt_within(const CaseSpec& c, double timeout_s) const {
    return attempt_trajectory(context_.runner,
                              with_setting(c, "timeout", format_number(timeout_s), false));
  }

  // A run killed by the cost budget (not by the probe timeout) marks the probe stopped.
  bool stopped_by_budget(const Trajectory& run, double timeout_s, const std::string& where,
                         Probe& probe) const {
    if (!timed_out(run) || timeout_s >= settings_.probe_timeout_s) return false;
    stop(probe, where + " ran past " + format_number(timeout_s) + " s, over " +
                    format_number(settings_.stop_factor) + " x");
    return true;
  }
  // `best_now`: the best's first frames (p10) measured beside the probe, where that raised
  // the yardstick; 0: its ms/frame was the yardstick.
  void stop(Probe& probe, const std::string& why, double best_now = 0) const {
    char best[96];
    int length = std::snprintf(best, sizeof best, " (%.4g ms/frame", context_.best.ms_per_frame);
    if (best_now > 0)
      std::snprintf(best + length, sizeof best - length, "; %.4g ms its first frames now",
                    best_now);
    probe.stopped = true;
    probe.why = "slower than " + context_.best.label + best + "): " + why;
  }

  CaseSpec first_frames_case(const CaseSpec& c) const {
    return with_setting(c, "duration", format_number(first_frames() / settings_.frame_rate), false);
  }
  double first_frames() const {
    return std::min<double>(cost_frames, settings_.duration * settings_.frame_rate);
  }

  // Stage 1, once some setting passed: the first frames at the scene's mesh. A setting is
  // stopped there when nothing in the bracket it tops, (failing, value] along the parameter
  // searched, can cost within stop_factor / 2 of the best's: it costs at least the setting's
  // frames x (failing + 1) / value (see bisect_at), and settings above it cost more. One that
  // diverges fails.
  bool judge_first_frames(const CaseSpec& c, uint32_t substeps, uint32_t iterations,
                          uint32_t failing, Probe& probe) {
    if (!context_.best.found() || settings_.stop_factor <= 0) return true;
    const double frames = first_frames();
    // The first frames are measured, not timed: they get the best's whole run as their wall
    // limit, a backstop for a setting whose frames take seconds each.
    const double timeout_s = budget_s(1.0);
    const CaseSpec short_case = first_frames_case(c);
    const Trajectory first = attempt_within(short_case, timeout_s);
    probe.ms_per_frame = first.ms_per_frame;
    if (stopped_by_budget(first, timeout_s, "its first frames", probe)) return false;
    // Cost first: over the budget, whether the setting is stable does not matter (more
    // substeps, which might be stable, cost more still). Judged on the fastest frames, and on
    // a second run before a stop: other jobs on the machine only ever slow frames down, and a
    // burst of them can outlast five frames.
    const uint32_t value = candidate_.has_iterations ? iterations : substeps;
    const double floor_fraction = (failing + 1.0) / value;
    const auto limit = [&](double best) {
      return settings_.stop_factor / 2 * best / floor_fraction;
    };
    if (first.ms_per_frame_p10 <= limit(context_.best.ms_per_frame))
      return judge_run(first, probe, "in its first frames") &&
             judge_stretch(first, probe, " in its first frames");
    const Trajectory again = attempt_within(short_case, timeout_s);
    const double fastest = again.verdict.stable() || !timed_out(again)
                               ? std::min(first.ms_per_frame_p10, again.ms_per_frame_p10)
                               : first.ms_per_frame_p10;
    // And beside the best's first frames measured now: a load that grew since the best was
    // measured slows both alike (the larger of the two is the yardstick).
    const Trajectory best_first = attempt_within(context_.best.first_frames, timeout_s);
    const double best_now = best_first.verdict.stable() ? best_first.ms_per_frame_p10 : 0.0;
    const double yardstick = std::max(context_.best.ms_per_frame, best_now);
    if (fastest <= limit(yardstick))
      return judge_run(first, probe, "in its first frames") &&
             judge_stretch(first, probe, " in its first frames");
    char cost[192];
    int length = std::snprintf(
        cost, sizeof cost, "its fastest of %g first frames took %.4g ms (twice)", frames, fastest);
    const uint32_t searched = candidate_.has_iterations ? substeps : 0;
    if (failing + 1 < value)
      std::snprintf(cost + length, sizeof cost - length,
                    ", so %u to %s cost at least %.4g ms/frame", failing + 1,
                    value_label(searched, value).c_str(), fastest * floor_fraction);
    stop(probe,
         cost + (", over " + format_number(settings_.stop_factor / 2) + " x (stop_factor / 2)"),
         best_now > context_.best.ms_per_frame ? best_now : 0.0);
    return false;
  }

  // Stage 2: the error, on the error mesh to the error T (the cheaper run).
  bool judge_error_run(const CaseSpec& c, Probe& probe) {
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
  bool judge_full_run(const CaseSpec& c, Probe& probe, double& wall_s) {
    const double timeout_s = budget_s(1.0);
    const Trajectory run = attempt_within(c, timeout_s);
    probe.ms_per_frame = run.ms_per_frame;
    probe.max_stretch = run.max_stretch;
    wall_s = run.wall_s;
    if (stopped_by_budget(run, timeout_s, "its run", probe) || !judge_run(run, probe, "") ||
        !judge_stretch(run, probe, ""))
      return false;
    return !same_error_run() || judge_error(run, probe);
  }

  // The run stops at the check that passes the limit (stability.stretch_stop).
  bool judge_stretch(const Trajectory& run, Probe& probe, const std::string& where) const {
    if (!(run.max_stretch > settings_.stretch_limit)) return true;
    probe.max_stretch = run.max_stretch;
    probe.why = "stretch " + format_number(run.max_stretch) + " above " +
                format_number(settings_.stretch_limit) + where;
    return false;
  }

  // False with probe.why set when the run was not stable; a probe-timeout ends the search.
  bool judge_run(const Trajectory& run, Probe& probe, const std::string& where) {
    if (run.verdict.stable()) return true;
    probe.why = (where.empty() ? "" : where + ": ") + to_string(run.verdict.status) + ": " +
                run.verdict.reason;
    if (timed_out(run))
      give_up("too slow: the run at " + current_label_ + (where.empty() ? "" : " " + where) +
              " ran past " + format_number(settings_.probe_timeout_s) +
              " s (choose.probe_timeout)");
    return false;
  }

  // `failing`: the largest value of the parameter searched known to fail below this one.
  const Probe& probe(uint32_t substeps, uint32_t iterations, uint32_t failing) {
    const auto known = probes_.find({substeps, iterations});
    if (known != probes_.end()) return known->second;
    const CaseSpec c = candidate_case(substeps, iterations);
    current_label_ = label_of(substeps, iterations);
    Probe probe;
    // Cheapest stages first: a setting that fails one needs none of the later runs.
    double wall_s = 0;
    probe.passed = judge_first_frames(c, substeps, iterations, failing, probe) &&
                   judge_error_run(c, probe) && judge_full_run(c, probe, wall_s);
    if (probe.passed) record_best(substeps, iterations, c, probe, wall_s);
    if (!probe.passed) last_failure_ = label_of(substeps, iterations) + ": " + probe.why;
    if (probe.stopped) {
      stop_substeps_ = true;
      if (candidate_.has_iterations) stopped_iterations_ = iterations;
      stopped_label_ = label_of(substeps, iterations);
      stopped_reason_ = probe.why;
    }
    const std::string note = judge_progress(substeps, iterations, probe);
    store_row(c, substeps, iterations, probe);
    print(substeps, iterations, probe, note);
    return probes_.emplace(std::make_pair(substeps, iterations), probe).first->second;
  }

  bool judge_error(const Trajectory& measured, Probe& probe) const {
    probe.error = relative_rms_error(measured.positions, context_.reference.positions,
                                     context_.reference.diagonal);
    if (probe.error <= settings_.error_tolerance) return true;
    probe.error_failed = true;
    probe.why = "error " + percent(probe.error) + " above " + percent(settings_.error_tolerance);
    return false;
  }

  void record_best(uint32_t substeps, uint32_t iterations, const CaseSpec& c, const Probe& probe,
                   double wall_s) {
    BestSoFar& best = context_.best;
    if (probe.ms_per_frame >= best.ms_per_frame) return;
    best.integrator = candidate_.integrator;
    best.label = candidate_.integrator + " at " + label_of(substeps, iterations);
    best.ms_per_frame = probe.ms_per_frame;
    best.wall_s = wall_s;
    best.first_frames = first_frames_case(c);
  }

  void give_up(std::string reason) {
    give_up_ = true;
    give_up_reason_ = std::move(reason);
  }

  // Early stops when going on cannot help (see the header); returns a note for the progress
  // line when it stops something.
  std::string judge_progress(uint32_t substeps, uint32_t iterations, const Probe& probe) {
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

  void store_row(const CaseSpec& c, uint32_t substeps, uint32_t iterations, const Probe& probe) {
    Row row;
    row["key"] = "choose;probe;" + c.key + ";substeps=" + std::to_string(substeps) +
                 ";iterations=" + std::to_string(iterations);
    row["kind"] = "probe";
    for (const auto& [name, value] : c.coordinates) row[name] = value;
    row["substeps"] = substeps;
    row["iterations"] = iterations;
    row["ms_per_frame"] = probe.ms_per_frame > 0 ? Row(probe.ms_per_frame) : Row();
    row["max_stretch"] = std::isfinite(probe.max_stretch) ? Row(probe.max_stretch) : Row();
    row["error"] = std::isfinite(probe.error) ? Row(probe.error) : Row();
    row["error_mesh"] = settings_.error_mesh.empty() ? "same" : settings_.error_mesh;
    row["passed"] = probe.passed;
    row["stopped"] = probe.stopped;
    row["why"] = probe.why;
    if (!context_.store.contains(row["key"].get<std::string>()))
      context_.store.append(row, c.index);
  }

  void print(uint32_t substeps, uint32_t iterations, const Probe& probe, const std::string& note) {
    const double elapsed =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - context_.start).count();
    char cost[48] = "";
    if (probe.ms_per_frame > 0)
      std::snprintf(cost, sizeof cost, " (%.4g ms/frame)", probe.ms_per_frame);
    context_.progress << "choose " << position_ << " " << candidate_.integrator << " "
                      << label_of(substeps, iterations) << ": "
                      << (probe.passed ? std::string("passes") : probe.why.substr(0, 320)) << cost
                      << note << " [" << Progress::format_duration(elapsed) << "]\n"
                      << std::flush;
  }

  CaseSpec base_;
  ChoiceCandidate candidate_;
  std::string position_;  // "[2/7]"
  SearchContext& context_;
  const ChoiceSettings& settings_;
  std::map<std::pair<uint32_t, uint32_t>, Probe> probes_;
  std::string last_failure_;
  bool give_up_ = false;  // the whole search ends
  std::string give_up_reason_;
  bool stop_substeps_ = false;                  // the search at this substep count ends
  uint32_t stopped_iterations_ = 0;             // the iterations of a probe stopped by the budget
  std::string stopped_label_, stopped_reason_;  // the last probe stopped by the budget
  // Why a bisection ended early, by the passing end it left.
  std::map<std::pair<uint32_t, uint32_t>, std::string> unrefined_;
  std::string current_label_;  // the setting being probed
};

}  // namespace

std::vector<Choice> choose_integrators(const SweepSpec& spec, const CaseSpec& base,
                                       const std::vector<ChoiceCandidate>& candidates,
                                       const ChoiceSettings& settings,
                                       const TrajectoryRunner& runner,
                                       const TrajectoryRunner& reference_runner,
                                       ResultsStore& store, std::ostream& progress) {
  CaseSpec error_base =
      with_setting(base, "duration", format_number(error_duration(settings)), false);
  if (!settings.error_mesh.empty())
    error_base = with_setting(error_base, "mesh", settings.error_mesh);
  const double reference_dt = 1.0 / (settings.frame_rate * settings.reference_substeps);
  const auto start = std::chrono::steady_clock::now();
  progress << "choose: reference " << settings.reference_integrator << " float64 at dt "
           << format_number(reference_dt)
           << " s and half that, to T = " << format_number(error_duration(settings)) << " s"
           << (settings.error_mesh.empty() ? "" : " on " + settings.error_mesh) << "\n"
           << std::flush;
  const Trajectory reference =
      compute_reference(spec, error_base, reference_dt, reference_runner, store);
  for (const Row& row : store.rows()) {
    if (row["kind"] != "reference") continue;
    const double difference = row["reference_difference"].get<double>();
    if (difference > settings.error_tolerance)
      throw SweepError("choose: the reference is not converged at T = " +
                       format_number(error_duration(settings)) +
                       " s: " + settings.reference_integrator + " float64 at dt " +
                       format_number(reference_dt) + " s and dt / 2 differ by " +
                       percent(difference) + " of the cloth diagonal, above the tolerance " +
                       percent(settings.error_tolerance) +
                       "; allowed: a shorter choose.error_duration (wind makes the flag's motion "
                       "chaotic) or more choose.reference_substeps");
    progress << "choose: reference done, estimated own error "
             << row["reference_error_estimate"].dump() << " of the diagonal ["
             << Progress::format_duration(
                    std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count())
             << "]\n"
             << std::flush;
  }
  SearchContext context{settings, runner, reference, store, progress, start, {}};
  std::vector<Choice> choices;
  for (std::size_t i = 0; i < candidates.size(); ++i) {
    const std::string position =
        "[" + std::to_string(i + 1) + "/" + std::to_string(candidates.size()) + "]";
    choices.push_back(IntegratorSearch(base, candidates[i], position, context).run());
  }
  std::stable_sort(choices.begin(), choices.end(), [](const Choice& a, const Choice& b) {
    if (a.passed != b.passed) return a.passed;
    return a.passed && a.ms_per_frame < b.ms_per_frame;
  });
  return choices;
}

std::vector<Row> choice_rows(const std::vector<Choice>& choices, const ChoiceSettings& settings) {
  std::vector<Row> rows;
  int rank = 0;
  for (const Choice& choice : choices) {
    Row row;
    row["key"] = "choose;choice;integrator=" + choice.integrator;
    row["rank"] = choice.passed ? Row(++rank) : Row();
    row["integrator"] = choice.integrator;
    row["substeps"] = choice.passed ? Row(choice.substeps) : Row();
    row["iterations"] = choice.passed && choice.iterations ? Row(choice.iterations) : Row();
    row["iterations_parameter"] =
        choice.passed && choice.iterations ? Row(choice.iterations_param) : Row();
    row["dt"] = choice.passed ? Row(1.0 / (settings.frame_rate * choice.substeps)) : Row();
    row["ms_per_frame"] = choice.passed ? Row(choice.ms_per_frame) : Row();
    row["real_time_factor"] =
        choice.passed ? Row(1e3 / settings.frame_rate / choice.ms_per_frame) : Row();
    row["error"] = choice.passed ? Row(choice.error) : Row();
    row["error_mesh"] = settings.error_mesh.empty() ? "same" : settings.error_mesh;
    row["max_stretch"] = choice.passed ? Row(choice.max_stretch) : Row();
    row["verdict"] = choice.verdict;
    row["probes"] = choice.probes;
    rows.push_back(row);
  }
  return rows;
}

std::string choice_table(const std::vector<Choice>& choices, const ChoiceSettings& settings) {
  std::string text;
  char line[512];
  std::snprintf(line, sizeof line, "%-4s %-20s %8s %10s %12s %8s %10s %11s  %s\n", "rank",
                "integrator", "substeps", "iterations", "ms/frame", "RTF", "error", "max stretch",
                "verdict");
  text += line;
  int rank = 0;
  for (const Choice& c : choices) {
    if (c.passed) {
      // implicit_euler's iterations are its CG cap: the cell names a parameter other than
      // "iterations".
      const std::string iterations = !c.iterations ? "-"
                                     : c.iterations_param == "iterations"
                                         ? std::to_string(c.iterations)
                                         : c.iterations_param + "=" + std::to_string(c.iterations);
      std::snprintf(line, sizeof line, "%-4d %-20s %8u %10s %12.4g %8.3g %10s %11s  %s\n", ++rank,
                    c.integrator.c_str(), c.substeps, iterations.c_str(), c.ms_per_frame,
                    1e3 / settings.frame_rate / c.ms_per_frame, percent(c.error).c_str(),
                    percent(c.max_stretch - 1).c_str(), c.verdict.c_str());
    } else {
      std::snprintf(line, sizeof line, "%-4s %-20s %8s %10s %12s %8s %10s %11s  %s\n", "-",
                    c.integrator.c_str(), "-", "-", "-", "-", "-", "-", c.verdict.c_str());
    }
    text += line;
  }
  return text;
}

}  // namespace clothlab::sweep
