#include "integrator_search.hpp"

#include <algorithm>
#include <functional>

#include "clothlab/sweep/case_attempt.hpp"

namespace clothlab::sweep::choice_detail {

namespace {

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

}  // namespace

double error_duration(const ChoiceSettings& settings) {
  return settings.error_duration > 0 ? settings.error_duration : settings.duration;
}

Choice IntegratorSearch::run() {
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
  choice.run = chosen.run;
  choice.verdict =
      chosen.ms_per_frame <= 1e3 / settings_.frame_rate ? "real time" : "slower than real time";
  if (const auto note = unrefined_.find(*best); note != unrefined_.end())
    choice.verdict += "; " + note->second;
  return choice;
}

// The search along substeps (substeps 0: the value is the substeps) or along the
// iterations at `substeps`: its probes' keys and the value's label.
std::pair<uint32_t, uint32_t> IntegratorSearch::key(uint32_t substeps, uint32_t value) const {
  return substeps ? std::make_pair(substeps, value) : std::make_pair(value, 0u);
}

std::string IntegratorSearch::value_label(uint32_t substeps, uint32_t value) const {
  return substeps ? std::to_string(value) + (value == 1 ? " iteration at " : " iterations at ") +
                        label_of(substeps, 0)
                  : label_of(value, 0);
}

// A bisection ended by the budget: its passing end stays, said so.
void IntegratorSearch::note_stopped_refining(uint32_t substeps, const Fewest& found) {
  if (!found.passing || !found.stopped_refining_at) return;
  unrefined_[key(substeps, *found.passing)] =
      "not refined below " + value_label(substeps, *found.passing) + ": " +
      value_label(substeps, found.stopped_refining_at) + " " +
      probes_.at(key(substeps, found.stopped_refining_at)).why;
}

// A passing setting lies above the failing ones along the parameter searched.
analysis::Side IntegratorSearch::side(const Probe& probe) {
  return probe.passed    ? analysis::Side::above
         : probe.stopped ? analysis::Side::stop
                         : analysis::Side::below;
}

uint32_t IntegratorSearch::max_iterations() const {
  return std::min(settings_.max_iterations, candidate_.iterations_limit);
}

CaseSpec IntegratorSearch::candidate_case(uint32_t substeps, uint32_t iterations) const {
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

bool IntegratorSearch::same_error_run() const {
  return settings_.error_mesh.empty() && error_duration(settings_) == settings_.duration;
}

CaseSpec IntegratorSearch::error_case(const CaseSpec& c) const {
  CaseSpec e = with_setting(c, "duration", format_number(error_duration(settings_)), false);
  e = with_setting(e, "stability.stretch_stop", "0", false);
  return settings_.error_mesh.empty() ? e : with_setting(e, "mesh", settings_.error_mesh);
}

Trajectory IntegratorSearch::attempt_within(const CaseSpec& c, double timeout_s) const {
  return attempt_trajectory(context_.runner,
                            with_setting(c, "timeout", format_number(timeout_s), false));
}

// `failing`: the largest value of the parameter searched known to fail below this one.
const Probe& IntegratorSearch::probe(uint32_t substeps, uint32_t iterations, uint32_t failing) {
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

void IntegratorSearch::give_up(std::string reason) {
  give_up_ = true;
  give_up_reason_ = std::move(reason);
}

}  // namespace clothlab::sweep::choice_detail
