// The parts of one integrator's search in choose_integrators (integrator_choice.hpp), shared
// by the files that hold them by concept: the search along substeps and iterations
// (integrator_search.cpp), the cost budget (choice_budget.cpp), the judging of a probe
// (probe_verdict.cpp), the probe's row and progress line (choice_report.cpp).
#pragma once

#include <chrono>
#include <clothlab/analysis/bracket_search.hpp>
#include <clothlab/host/param_text.hpp>
#include <cmath>
#include <cstdint>
#include <map>
#include <optional>
#include <ostream>
#include <string>
#include <utility>

#include "clothlab/sweep/integrator_choice.hpp"

namespace clothlab::sweep::choice_detail {

using host::format_number;

// What the runs of one setting (substeps, iterations) found.
struct Probe {
  bool passed = false;
  bool error_failed = false;  // failed on the error criterion (the other runs were fine)
  bool stopped = false;       // killed by the cost budget: slower than the best verdict so far
  double ms_per_frame = 0, error = NAN;
  // The figures of its run at the scene's mesh: the run over T, or its first frames where they
  // failed on stretch or penetration; empty while neither was judged.
  std::optional<host::RunSummary> run;
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

// A search along one parameter: the fewest passing value found (none: nothing passed, or the
// cost budget stopped the doubling), and the value whose stop ended the bisection, if one did.
struct Fewest {
  std::optional<uint32_t> passing;
  uint32_t stopped_refining_at = 0;
};

// "12.3 %" for 0.123, to `digits` significant digits.
std::string percent(double fraction, int digits = 3);
// Both fractions as percents, with the fewest digits (3 or more) that tell them apart, so that a
// comparison never reads "1 % above 1 %".
std::pair<std::string, std::string> percents_apart(double fraction, double other);
// "8 substeps x 4 iterations"; iterations 0: the method has none.
std::string label_of(uint32_t substeps, uint32_t iterations);
// The T of the error runs (integrator_search.cpp).
double error_duration(const ChoiceSettings& settings);
// A run killed at its wall-clock limit (probe_verdict.cpp).
bool timed_out(const Trajectory& run);

class IntegratorSearch {
 public:
  IntegratorSearch(const CaseSpec& base, const ChoiceCandidate& candidate, std::string position,
                   SearchContext& context)
      : base_(with_setting(base, "integrator.plugin", candidate.integrator)),
        candidate_(candidate),
        position_(std::move(position)),
        context_(context),
        settings_(context.settings) {}

  // The cheapest passing setting of the candidate, or why there is none.
  Choice run();

 private:
  // The search along substeps and iterations, and the cases it runs (integrator_search.cpp).
  std::pair<uint32_t, uint32_t> key(uint32_t substeps, uint32_t value) const;
  std::string value_label(uint32_t substeps, uint32_t value) const;
  void note_stopped_refining(uint32_t substeps, const Fewest& found);
  static analysis::Side side(const Probe& probe);
  uint32_t max_iterations() const;
  CaseSpec candidate_case(uint32_t substeps, uint32_t iterations) const;
  bool same_error_run() const;
  CaseSpec error_case(const CaseSpec& c) const;
  Trajectory attempt_within(const CaseSpec& c, double timeout_s) const;
  const Probe& probe(uint32_t substeps, uint32_t iterations, uint32_t failing);
  void give_up(std::string reason);

  // The cost budget: the yardstick, run time limits, stops and where to bisect
  // (choice_budget.cpp).
  std::optional<uint32_t> bisect_at(uint32_t substeps, uint32_t failing, uint32_t passing);
  double error_work_fraction() const;
  double budget_s(double work_fraction) const;
  bool stopped_by_budget(const Trajectory& run, double timeout_s, const std::string& where,
                         Probe& probe) const;
  void stop(Probe& probe, const std::string& why, double best_now = 0) const;
  CaseSpec first_frames_case(const CaseSpec& c) const;
  double first_frames() const;
  void record_best(uint32_t substeps, uint32_t iterations, const CaseSpec& c, const Probe& probe,
                   double wall_s);

  // Judging a probe: its three runs, cheapest first, and the early stops their errors allow
  // (probe_verdict.cpp).
  bool judge_first_frames(const CaseSpec& c, uint32_t substeps, uint32_t iterations,
                          uint32_t failing, Probe& probe);
  bool judge_error_run(const CaseSpec& c, Probe& probe);
  bool judge_full_run(const CaseSpec& c, Probe& probe, double& wall_s);
  bool judge_stretch(const Trajectory& run, Probe& probe, const std::string& where) const;
  bool judge_penetration(const Trajectory& run, Probe& probe, const std::string& where) const;
  bool judge_run(const Trajectory& run, Probe& probe, const std::string& where);
  bool judge_error(const Trajectory& measured, Probe& probe) const;
  bool judge_stretch_against_reference(const Trajectory& measured, Probe& probe) const;
  std::string judge_progress(uint32_t substeps, uint32_t iterations, const Probe& probe);

  // The probe's row in the store and its progress line (choice_report.cpp).
  void store_row(const CaseSpec& c, uint32_t substeps, uint32_t iterations, const Probe& probe);
  void print(uint32_t substeps, uint32_t iterations, const Probe& probe, const std::string& note);

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

}  // namespace clothlab::sweep::choice_detail
