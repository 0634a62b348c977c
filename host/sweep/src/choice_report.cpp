#include <cmath>
#include <cstdio>
#include <optional>

#include "clothlab/sweep/progress.hpp"
#include "clothlab/sweep/sweep_error.hpp"
#include "integrator_search.hpp"

namespace clothlab::sweep {
namespace {

// The figures of a run at the scene's mesh that probe and choice rows carry: null without the
// run, and for a figure it lacks (no colliders) or that is not finite.
void put_run_figures(Row& row, const std::optional<host::RunSummary>& run) {
  const auto figure = [&](double (*of)(const host::RunSummary&)) {
    const double value = run ? of(*run) : NAN;
    return std::isfinite(value) ? Row(value) : Row();
  };
  (run ? *run : host::RunSummary{}).visit_stretch_over_run([&](const char* name, double value) {
    row[name] = run && std::isfinite(value) ? Row(value) : Row();
  });
  row["max_penetration"] = figure([](const host::RunSummary& r) { return r.max_penetration(); });
  row["collider_thickness"] =
      figure([](const host::RunSummary& r) { return r.collider_thickness(); });
}

}  // namespace

namespace choice_detail {

std::string percent(double fraction, int digits) {
  char text[32];
  std::snprintf(text, sizeof text, "%.*g %%", digits, 100 * fraction);
  return text;
}

std::pair<std::string, std::string> percents_apart(double fraction, double other) {
  constexpr int most_digits = 9;
  for (int digits = 3;; ++digits) {
    std::pair<std::string, std::string> texts{percent(fraction, digits), percent(other, digits)};
    if (texts.first != texts.second || digits == most_digits) return texts;
  }
}

std::string label_of(uint32_t substeps, uint32_t iterations) {
  return std::to_string(substeps) + (substeps == 1 ? " substep" : " substeps") +
         (iterations ? " x " + std::to_string(iterations) +
                           (iterations == 1 ? " iteration" : " iterations")
                     : "");
}

void IntegratorSearch::store_row(const CaseSpec& c, uint32_t substeps, uint32_t iterations,
                                 const Probe& probe) {
  Row row;
  row["key"] = "choose;probe;" + c.key + ";substeps=" + std::to_string(substeps) +
               ";iterations=" + std::to_string(iterations);
  row["kind"] = "probe";
  for (const auto& [name, value] : c.coordinates) row[name] = value;
  row["substeps"] = substeps;
  row["iterations"] = iterations;
  row["ms_per_frame"] = probe.ms_per_frame > 0 ? Row(probe.ms_per_frame) : Row();
  put_run_figures(row, probe.run);
  row["error"] = std::isfinite(probe.error) ? Row(probe.error) : Row();
  row["error_mesh"] = settings_.error_mesh.empty() ? "same" : settings_.error_mesh;
  row["passed"] = probe.passed;
  row["stopped"] = probe.stopped;
  row["why"] = probe.why;
  if (!context_.store.contains(row["key"].get<std::string>())) context_.store.append(row, c.index);
}

void IntegratorSearch::print(uint32_t substeps, uint32_t iterations, const Probe& probe,
                             const std::string& note) {
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

}  // namespace choice_detail

using choice_detail::percent;

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
    put_run_figures(row, choice.run);
    row["predicted_substeps"] = choice.predicted_substeps ? Row(choice.predicted_substeps) : Row();
    row["verdict"] = choice.verdict;
    row["probes"] = choice.probes;
    rows.push_back(row);
  }
  return rows;
}

std::string choice_table(const std::vector<Choice>& choices, const ChoiceSettings& settings) {
  std::string text;
  char line[512];
  // "stretch": the robust figure judged (away from the pins); "max stretch": at the pins too.
  // "penetration": the deepest into a collider over the run (m), on scenes with colliders.
  std::snprintf(line, sizeof line, "%-4s %-20s %8s %10s %12s %8s %10s %8s %11s %11s  %s\n", "rank",
                "integrator", "substeps", "iterations", "ms/frame", "RTF", "error", "stretch",
                "max stretch", "penetration", "verdict");
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
      const double deepest = c.run ? c.run->max_penetration() : NAN;
      const double stretch = c.run ? c.run->max_stretch_away_from_pins.over_run : NAN;
      const double max_stretch = c.run ? c.run->max_stretch.over_run : NAN;
      char penetration[32] = "-";
      if (std::isfinite(deepest)) std::snprintf(penetration, sizeof penetration, "%.3g m", deepest);
      std::snprintf(line, sizeof line, "%-4d %-20s %8u %10s %12.4g %8.3g %10s %8s %11s %11s  %s\n",
                    ++rank, c.integrator.c_str(), c.substeps, iterations.c_str(), c.ms_per_frame,
                    1e3 / settings.frame_rate / c.ms_per_frame, percent(c.error).c_str(),
                    percent(stretch - 1).c_str(), percent(max_stretch - 1).c_str(), penetration,
                    c.verdict.c_str());
    } else {
      std::snprintf(line, sizeof line, "%-4s %-20s %8s %10s %12s %8s %10s %8s %11s %11s  %s\n", "-",
                    c.integrator.c_str(), "-", "-", "-", "-", "-", "-", "-", "-",
                    c.verdict.c_str());
    }
    text += line;
  }
  return text;
}

namespace {

// A stored row's figure by name; a missing or null one is a SweepError naming it and the row.
const Row& figure_of(const Row& row, const std::string& what, const std::string& name) {
  const auto found = row.find(name);
  if (found == row.end() || found->is_null())
    throw SweepError("choose: the " + what + " row has no " + name);
  return *found;
}

double number_of(const Row& row, const std::string& what, const std::string& name) {
  const Row& value = figure_of(row, what, name);
  if (!value.is_number())
    throw SweepError("choose: the " + what + " row's " + name + " is " + value.dump() +
                     ", not a number");
  return value.get<double>();
}

}  // namespace

std::string reference_line(const Row& reference) {
  if (!reference.is_object()) throw SweepError("choose: no reference row in the results");
  const auto number = [&](const std::string& name) {
    return number_of(reference, "reference", name);
  };
  std::string stretch;
  host::RunSummary{}.visit_stretch_over_run([&](const char* name, double) {
    stretch +=
        std::string(stretch.empty() ? "" : ", ") + name + " " + host::format_number(number(name));
  });
  return figure_of(reference, "reference", "reference_integrator").get<std::string>() +
         " float64, dt " + host::format_number(number("reference_dt")) +
         " s, estimated own error " +
         host::format_number(100 * number("reference_error_estimate")) +
         " % of the diagonal; stretch over the run: " + stretch;
}

std::string precision_floor_line(const Row& floor) {
  const std::string what = "precision_floor";
  const std::string precision = figure_of(floor, what, "precision").get<std::string>();
  return precision +
         " floor: " + figure_of(floor, what, "reference_integrator").get<std::string>() + " " +
         precision + " at dt " + host::format_number(number_of(floor, what, "dt")) + " s is " +
         host::format_number(100 * number_of(floor, what, "precision_floor")) +
         " % of the diagonal from its float64 run";
}

}  // namespace clothlab::sweep
