#include "clothlab/sweep/integrator_choice.hpp"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <exception>
#include <functional>
#include <map>
#include <optional>

#include "clothlab/sweep/number_text.hpp"
#include "clothlab/sweep/progress.hpp"
#include "clothlab/sweep/sweep_error.hpp"

namespace clothlab::sweep {
namespace {

struct Probe {
  bool passed = false;
  double ms_per_frame = 0, error = NAN, max_stretch = NAN;
  std::string why;  // the failed criterion; empty when passed
};

// The fewest n in [1, max] with passes(n), assuming passes is monotone: doubling from 1, then
// bisection until the bracket is within 10 % (each probe is a full run, so not to the unit).
std::optional<uint32_t> fewest(uint32_t max, const std::function<bool(uint32_t)>& passes,
                               const bool& give_up) {
  uint32_t failing = 0, n = 1;
  while (!passes(n)) {
    if (n >= max || give_up) return std::nullopt;
    failing = n;
    n = std::min(max, 2 * n);
  }
  uint32_t passing = n;
  while (passing - failing > 1 && passing > failing + failing / 10) {
    const uint32_t middle = failing + (passing - failing) / 2;
    (passes(middle) ? passing : failing) = middle;
  }
  return passing;
}

std::string percent(double fraction) {
  char text[32];
  std::snprintf(text, sizeof text, "%.3g %%", 100 * fraction);
  return text;
}

double error_duration(const ChoiceSettings& settings) {
  return settings.error_duration > 0 ? settings.error_duration : settings.duration;
}

class IntegratorSearch {
 public:
  IntegratorSearch(const SweepSpec& spec, const CaseSpec& base, const ChoiceCandidate& candidate,
                   const ChoiceSettings& settings, const TrajectoryRunner& runner,
                   const Trajectory& reference, ResultsStore& store, std::ostream& progress)
      : spec_(spec),
        base_(with_setting(base, "integrator.plugin", candidate.integrator)),
        candidate_(candidate),
        settings_(settings),
        runner_(runner),
        reference_(reference),
        store_(store),
        progress_(progress),
        start_(std::chrono::steady_clock::now()) {}

  Choice run() {
    Choice choice;
    choice.integrator = candidate_.integrator;
    std::optional<std::pair<uint32_t, uint32_t>> best;  // (substeps, iterations)
    if (!candidate_.has_iterations) {
      if (const auto substeps = fewest(
              settings_.max_substeps, [&](uint32_t s) { return probe(s, 0).passed; }, give_up_))
        best = {{*substeps, 0}};
    } else {
      // Cost ~ substeps x iterations: walk the substeps up while the cheapest passing
      // iteration count keeps lowering the cost per frame.
      for (uint32_t substeps = 1; substeps <= settings_.max_substeps; substeps *= 2) {
        const auto iterations = fewest(
            settings_.max_iterations, [&](uint32_t it) { return probe(substeps, it).passed; },
            give_up_);
        if (give_up_) break;
        if (!iterations) continue;
        const double cost = probes_.at({substeps, *iterations}).ms_per_frame;
        if (best && cost >= probes_.at(*best).ms_per_frame) break;
        best = {{substeps, *iterations}};
        if (*iterations == 1) break;  // more substeps only cost more
      }
    }
    choice.probes = static_cast<int>(probes_.size());
    if (!best && !give_up_reason_.empty()) {
      choice.verdict = give_up_reason_;
      return choice;
    }
    if (!best) {
      choice.verdict = "no setting passed up to " + std::to_string(settings_.max_substeps) +
                       " substeps" +
                       (candidate_.has_iterations
                            ? " x " + std::to_string(settings_.max_iterations) + " iterations"
                            : std::string()) +
                       "; last: " + last_failure_;
      return choice;
    }
    const Probe& chosen = probes_.at(*best);
    choice.passed = true;
    choice.substeps = best->first;
    choice.iterations = best->second;
    choice.ms_per_frame = chosen.ms_per_frame;
    choice.error = chosen.error;
    choice.max_stretch = chosen.max_stretch;
    choice.verdict =
        chosen.ms_per_frame <= 1e3 / settings_.frame_rate ? "real time" : "slower than real time";
    return choice;
  }

 private:
  CaseSpec candidate_case(uint32_t substeps, uint32_t iterations) const {
    CaseSpec c = with_setting(base_, "frame_rate", format_number(settings_.frame_rate), false);
    c = with_setting(c, "timeout", format_number(settings_.probe_timeout_s), false);
    c = with_setting(c, "substeps", std::to_string(substeps));
    if (candidate_.has_own_substeps) c = with_setting(c, "integrator.substeps", "1", false);
    if (iterations > 0) c = with_setting(c, "integrator.iterations", std::to_string(iterations));
    return c;
  }

  bool same_error_run() const {
    return settings_.error_mesh.empty() && error_duration(settings_) == settings_.duration;
  }
  CaseSpec error_case(const CaseSpec& c) const {
    CaseSpec e = with_setting(c, "duration", format_number(error_duration(settings_)), false);
    return settings_.error_mesh.empty() ? e : with_setting(e, "mesh", settings_.error_mesh);
  }

  Trajectory run_guarded(const CaseSpec& c) const {
    try {
      return runner_(c);
    } catch (const std::exception& error) {
      Trajectory failed;
      failed.verdict.status = CaseStatus::Failed;
      failed.verdict.reason = error.what();
      return failed;
    }
  }

  const Probe& probe(uint32_t substeps, uint32_t iterations) {
    const auto known = probes_.find({substeps, iterations});
    if (known != probes_.end()) return known->second;
    const CaseSpec c = candidate_case(substeps, iterations);
    Probe probe;
    const Trajectory run = run_guarded(c);
    probe.ms_per_frame = run.ms_per_frame;
    probe.max_stretch = run.max_stretch;
    if (!run.verdict.stable()) {
      probe.why = std::string(to_string(run.verdict.status)) + ": " + run.verdict.reason;
    } else if (run.max_stretch > settings_.stretch_limit) {
      probe.why = "stretch " + format_number(run.max_stretch) + " above " +
                  format_number(settings_.stretch_limit);
    } else {
      const Trajectory measured = same_error_run() ? run : run_guarded(error_case(c));
      if (!measured.verdict.stable()) {
        probe.why = "on the error mesh " + settings_.error_mesh + ": " + measured.verdict.reason;
      } else {
        probe.error =
            relative_rms_error(measured.positions, reference_.positions, reference_.diagonal);
        probe.passed = probe.error <= settings_.error_tolerance;
        if (!probe.passed)
          probe.why = "error " + format_number(probe.error) + " above " +
                      format_number(settings_.error_tolerance);
      }
    }
    if (!probe.passed) last_failure_ = std::to_string(substeps) + " substeps: " + probe.why;
    judge_give_up(substeps, iterations, run, probe);
    store_row(c, substeps, iterations, probe);
    print(substeps, iterations, probe);
    return probes_.emplace(std::make_pair(substeps, iterations), probe).first->second;
  }

  // Sets give_up_ when going on cannot help (see the header).
  void judge_give_up(uint32_t substeps, uint32_t iterations, const Trajectory& run,
                     const Probe& probe) {
    const std::string label =
        std::to_string(substeps) + " substeps" +
        (iterations ? " x " + std::to_string(iterations) + " iterations" : "");
    if (run.verdict.status == CaseStatus::Failed &&
        run.verdict.reason.find("timed out") != std::string::npos) {
      give_up_ = true;
      give_up_reason_ = "too slow: a probe at " + label + " ran past " +
                        format_number(settings_.probe_timeout_s) + " s";
      return;
    }
    if (!std::isfinite(probe.error) || probe.passed) return;
    // Same iterations, half the step: compare with the probe at substeps / 2.
    const auto coarser = probes_.find({substeps / 2, iterations});
    if (substeps >= 2 && coarser != probes_.end() && std::isfinite(coarser->second.error) &&
        !coarser->second.passed &&
        std::abs(probe.error - coarser->second.error) < 0.1 * probe.error) {
      give_up_ = true;
      give_up_reason_ = "converges elsewhere: error " + percent(probe.error) + " at " + label +
                        ", " + percent(coarser->second.error) + " at half the substeps";
    }
  }

  void store_row(const CaseSpec& c, uint32_t substeps, uint32_t iterations, const Probe& probe) {
    Row row;
    row["key"] = "choose;probe;" + c.key + ";substeps=" + std::to_string(substeps) +
                 ";iterations=" + std::to_string(iterations);
    row["kind"] = "probe";
    for (const auto& [name, value] : c.coordinates) row[name] = value;
    row["substeps"] = substeps;
    row["iterations"] = iterations;
    row["ms_per_frame"] = probe.ms_per_frame;
    row["max_stretch"] = std::isfinite(probe.max_stretch) ? Row(probe.max_stretch) : Row();
    row["error"] = std::isfinite(probe.error) ? Row(probe.error) : Row();
    row["error_mesh"] = settings_.error_mesh.empty() ? "same" : settings_.error_mesh;
    row["passed"] = probe.passed;
    row["why"] = probe.why;
    if (!store_.contains(row["key"].get<std::string>())) store_.append(row);
  }

  void print(uint32_t substeps, uint32_t iterations, const Probe& probe) {
    const double elapsed =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
    char line[256];
    std::snprintf(line, sizeof line, "choose: %s %u substeps%s%s: %s (%.3g ms/frame) [%s]\n",
                  candidate_.integrator.c_str(), substeps, iterations ? " x " : "",
                  iterations ? (std::to_string(iterations) + " iterations").c_str() : "",
                  probe.passed ? "passes" : probe.why.substr(0, 120).c_str(), probe.ms_per_frame,
                  Progress::format_duration(elapsed).c_str());
    progress_ << line << std::flush;
  }

  const SweepSpec& spec_;
  CaseSpec base_;
  ChoiceCandidate candidate_;
  const ChoiceSettings& settings_;
  const TrajectoryRunner& runner_;
  const Trajectory& reference_;
  ResultsStore& store_;
  std::ostream& progress_;
  std::chrono::steady_clock::time_point start_;
  std::map<std::pair<uint32_t, uint32_t>, Probe> probes_;
  std::string last_failure_;
  bool give_up_ = false;
  std::string give_up_reason_;
};

}  // namespace

std::vector<Choice> choose_integrators(const SweepSpec& spec, const CaseSpec& base,
                                       const std::vector<ChoiceCandidate>& candidates,
                                       const ChoiceSettings& settings,
                                       const TrajectoryRunner& runner, ResultsStore& store,
                                       std::ostream& progress) {
  CaseSpec error_base =
      with_setting(base, "duration", format_number(error_duration(settings)), false);
  if (!settings.error_mesh.empty())
    error_base = with_setting(error_base, "mesh", settings.error_mesh);
  const double reference_dt = 1.0 / (settings.frame_rate * settings.reference_substeps);
  progress << "choose: reference " << settings.reference_integrator << " float64 at dt "
           << format_number(reference_dt)
           << " s and half that, to T = " << format_number(error_duration(settings)) << " s"
           << (settings.error_mesh.empty() ? "" : " on " + settings.error_mesh) << "\n"
           << std::flush;
  const Trajectory reference = compute_reference(spec, error_base, reference_dt, runner, store);
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
  }
  std::vector<Choice> choices;
  for (const ChoiceCandidate& candidate : candidates)
    choices.push_back(
        IntegratorSearch(spec, base, candidate, settings, runner, reference, store, progress)
            .run());
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
      std::snprintf(line, sizeof line, "%-4d %-20s %8u %10s %12.4g %8.3g %10s %11s  %s\n", ++rank,
                    c.integrator.c_str(), c.substeps,
                    c.iterations ? std::to_string(c.iterations).c_str() : "-", c.ms_per_frame,
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
