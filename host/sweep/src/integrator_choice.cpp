#include "clothlab/sweep/integrator_choice.hpp"

#include <algorithm>
#include <chrono>

#include "clothlab/sweep/progress.hpp"
#include "clothlab/sweep/sweep_error.hpp"
#include "integrator_search.hpp"

namespace clothlab::sweep {

using choice_detail::error_duration;
using choice_detail::percent;
using choice_detail::percents_apart;
using host::format_number;

namespace {

// What the candidate lacks of what the scene needs (the reference's run shows the scene's
// attachments and colliders), as "refused: ..."; empty when nothing.
std::string refusal(const ChoiceCandidate& candidate, const Trajectory& reference) {
  std::string missing;
  if (reference.summary.attached_particles() > 0 && !candidate.moves_attachments)
    missing =
        "does not move attachments (no CLOTHLAB_TRAIT_MOVES_ATTACHMENTS), which the "
        "scene's " +
        std::to_string(reference.summary.attached_particles()) + " attached particle(s) need";
  if (reference.summary.colliders() > 0 && !candidate.resolves_contacts)
    missing += (missing.empty() ? "" : "; ") +
               std::string(
                   "does not resolve contacts (no CLOTHLAB_TRAIT_RESOLVES_CONTACTS), "
                   "which the scene's ") +
               std::to_string(reference.summary.colliders()) + " collider(s) need";
  return missing.empty() ? "" : "refused: " + missing;
}

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
    const auto [gap, tolerance] = percents_apart(difference, settings.error_tolerance);
    if (difference > settings.error_tolerance)
      throw SweepError("choose: the reference is not converged at T = " +
                       format_number(error_duration(settings)) +
                       " s: " + settings.reference_integrator + " float64 at dt " +
                       format_number(reference_dt) + " s and dt / 2 differ by " + gap +
                       " of the cloth diagonal, above the tolerance " + tolerance +
                       "; allowed: a shorter choose.error_duration (wind makes the flag's motion "
                       "chaotic) or more choose.reference_substeps");
    progress << "choose: reference done, estimated own error "
             << row["reference_error_estimate"].dump() << " of the diagonal ["
             << Progress::format_duration(
                    std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count())
             << "]\n"
             << std::flush;
  }
  const double floor =
      compute_precision_floor(spec, error_base, reference_dt, reference, reference_runner, store);
  const auto [floor_text, tolerance] = percents_apart(floor, settings.error_tolerance);
  if (floor > settings.error_tolerance)
    throw SweepError("choose: " + error_base.precision +
                     " cannot meet the tolerance here: " + settings.reference_integrator + " " +
                     error_base.precision + " at the reference's step is " + floor_text +
                     " of the cloth diagonal from its float64 run at T = " +
                     format_number(error_duration(settings)) + " s, above choose.error_tolerance " +
                     tolerance + "; allowed: choose.error_tolerance above " + floor_text +
                     ", precision float64, or a shorter choose.error_duration");
  if (error_base.precision != "float64")
    progress << "choose: " << error_base.precision << " floor " << percent(floor)
             << " of the diagonal (" << settings.reference_integrator << " " << error_base.precision
             << " at the reference's step)\n"
             << std::flush;
  choice_detail::SearchContext context{settings, runner, reference, store, progress, start, {}};
  std::vector<Choice> choices;
  for (std::size_t i = 0; i < candidates.size(); ++i) {
    // Appended to, not "[" + ...: GCC 12 warns falsely (-Wrestrict) on that here.
    std::string position = "[";
    position += std::to_string(i + 1) + "/" + std::to_string(candidates.size()) + "]";
    const ChoiceCandidate& candidate = candidates[i];
    if (const std::string refused = refusal(candidate, reference); !refused.empty()) {
      progress << "choose " << position << " " << candidate.integrator << ": " << refused << "\n"
               << std::flush;
      Choice choice;
      choice.integrator = candidate.integrator;
      choice.verdict = refused;
      choices.push_back(choice);
      continue;
    }
    const std::string predicted = candidate.predicted_substeps == 0
                                      ? std::string()
                                      : "the m / h^2 bound predicts " +
                                            std::to_string(candidate.predicted_substeps) +
                                            " substeps or more (" + candidate.prediction + ")";
    if (!predicted.empty())
      progress << "choose " << position << " " << candidate.integrator << ": " << predicted << "\n"
               << std::flush;
    Choice choice = choice_detail::IntegratorSearch(base, candidate, position, context).run();
    choice.predicted_substeps = candidate.predicted_substeps;
    if (!predicted.empty()) choice.verdict += "; " + predicted;
    choices.push_back(choice);
  }
  std::stable_sort(choices.begin(), choices.end(), [](const Choice& a, const Choice& b) {
    if (a.passed != b.passed) return a.passed;
    return a.passed && a.ms_per_frame < b.ms_per_frame;
  });
  return choices;
}

}  // namespace clothlab::sweep
