#include "choose_mode.hpp"

#include <clothlab/ext/integrator_traits.h>

#include <algorithm>
#include <clothlab/analysis/local_solve_bound.hpp>
#include <clothlab/host/errors.hpp>
#include <clothlab/host/param_text.hpp>
#include <clothlab/host/plugin_library.hpp>
#include <clothlab/sweep/integrator_choice.hpp>
#include <clothlab/sweep/sweep_error.hpp>
#include <clothlab/sweep/trajectory_cache.hpp>
#include <cstdio>
#include <iostream>

#include "case_execution.hpp"
#include "dry_run.hpp"
#include "last_setting.hpp"
#include "output_file.hpp"
#include "run_config.hpp"
#include "sweep_mode.hpp"

namespace clothlab::cli {

namespace {

// The integrators to search, in plugin-path order unless choose.integrators names them.
std::vector<sweep::ChoiceCandidate> candidates_for(const Configuration& whole,
                                                   const std::vector<Setting>& settings,
                                                   const host::PluginSearchPath& search_path) {
  const host::LibraryScan scan = host::scan_libraries(search_path);
  std::vector<sweep::ChoiceCandidate> found;
  const uint32_t precision = whole.run.float64 ? CLOTHLAB_FLOAT64 : CLOTHLAB_FLOAT32;
  for (const host::PluginLibrary& library : scan.libraries)
    for (const host::IntegratorPlugin& integrator : library.integrators()) {
      if (!integrator.supports_precision(precision)) continue;
      sweep::ChoiceCandidate candidate{std::string(integrator.info().id), false};
      // The plugin names its substeps and iterations parameters in its traits (ABI 1.2);
      // older plugins are read by the parameters' conventional names.
      const auto* traits = static_cast<const clothlab_integrator_traits*>(
          integrator.extension(CLOTHLAB_EXT_INTEGRATOR_TRAITS));
      if (traits != nullptr && traits->struct_size >= sizeof(clothlab_integrator_traits)) {
        candidate.iterations_param = traits->iterations_param ? traits->iterations_param : "";
        candidate.substeps_param = traits->substeps_param ? traits->substeps_param : "";
        candidate.solves_locally = (traits->flags & CLOTHLAB_TRAIT_LOCAL_SOLVES) != 0;
        candidate.moves_attachments = (traits->flags & CLOTHLAB_TRAIT_MOVES_ATTACHMENTS) != 0;
        candidate.resolves_contacts = (traits->flags & CLOTHLAB_TRAIT_RESOLVES_CONTACTS) != 0;
      }
      const host::ParamSet params = integrator.default_params();
      for (const clothlab_param_spec& spec : params.specs()) {
        if (spec.name == candidate.iterations_param) {
          candidate.has_iterations = true;
          candidate.iterations_limit = static_cast<uint32_t>(std::min(spec.max_value, 1e9));
        }
        if (spec.name == candidate.substeps_param) candidate.has_own_substeps = true;
      }
      found.push_back(candidate);
    }
  if (whole.choose.integrators.empty()) return found;
  std::vector<sweep::ChoiceCandidate> chosen;
  for (const std::string& id : whole.choose.integrators) {
    const auto match = std::find_if(found.begin(), found.end(), [&](const auto& candidate) {
      return candidate.integrator == id;
    });
    if (match == found.end())
      throw host::InputError(where_set(settings, "choose.integrators") + ": " + id +
                             " is not an integrator on the plugin path (" + search_path.describe() +
                             ")");
    chosen.push_back(*match);
  }
  return chosen;
}

// The m / h^2 bound of each local solver on the scene (in the worker: the scene is the
// scenario plugin's), as the fewest substeps per frame.
void predict_local_solvers(std::vector<sweep::ChoiceCandidate>& candidates,
                           const sweep::CaseSpec& base, double frame_rate, CaseWorker& worker) {
  for (sweep::ChoiceCandidate& candidate : candidates) {
    if (!candidate.solves_locally) continue;
    nlohmann::json bound;
    try {
      bound =
          worker.local_solve(sweep::with_setting(base, "integrator.plugin", candidate.integrator));
    } catch (const host::InputError&) {
      // The scene refuses the candidate (an attachment or a collider it cannot handle): the
      // search lists it as refused with that reason; any other input error recurs at its
      // first probe.
      continue;
    }
    if (!bound.is_object() || !bound["dt_max"].is_number()) continue;
    analysis::LocalSolveBound figures;
    figures.dt_max = bound["dt_max"].get<double>();
    candidate.predicted_substeps = figures.substeps_per_frame(frame_rate);
    char how[160];
    std::snprintf(how, sizeof how, "h <= sqrt(m / ks) = sqrt(%.3g kg / %.4g N/m) = %.3g s",
                  bound["particle_mass"].get<double>(), bound["stiffness"].get<double>(),
                  figures.dt_max);
    candidate.prediction = how;
  }
}

// The scene's mesh as its settings give it ("200x200"), so that tables across meshes can be
// drawn from the ranked files alone (tools/plot.py scaling); null where the scenario's own
// default size stands.
nlohmann::ordered_json scene_mesh(const RunConfig& run) {
  std::string rows, cols;
  for (const Setting& setting : run.scenario_params) {
    if (setting.key == "rows") rows = setting.value;
    if (setting.key == "cols") cols = setting.value;
  }
  if (rows.empty() || cols.empty()) return nullptr;
  return rows + "x" + cols;
}

bool is_frame_or_choice_key(const std::string& key) {
  return key == "frame_rate" || key == "substeps" || key == "dt" || key.starts_with("choose.") ||
         key == "integrator.plugin";
}

}  // namespace

void run_choose(const std::vector<Setting>& settings, const host::PluginSearchPath& search_path,
                std::ostream& out, bool dry_run) {
  const Configuration whole = resolve_configuration(settings);
  const ChooseConfig& choose = whole.choose;
  if (std::none_of(settings.begin(), settings.end(),
                   [](const Setting& setting) { return setting.key == "frame_rate"; }))
    throw host::InputError("--choose needs frame_rate (Hz): --frame-rate 60 or frame_rate: 60");
  const sweep::ChoiceSettings& choice = choose.search;
  std::vector<sweep::ChoiceCandidate> candidates = candidates_for(whole, settings, search_path);
  if (candidates.empty())
    throw host::InputError("--choose: no integrator on the plugin path (" + search_path.describe() +
                           ")");

  // The scene is checked before the results store is opened: a failed reference run would
  // report a scenario that cannot be loaded without where it was set. Each candidate brings
  // its own integrator, so the reference integrator stands in for it.
  RunConfig scene = whole.run;
  scene.integrator = choice.reference_integrator;
  scene.integrator_source = where_set(settings, "choose.reference_integrator");
  scene.integrator_params.clear();
  check_plugins(scene, search_path);

  // The scene as every case sees it; frame settings are per candidate, the integrator per search.
  sweep::SweepSpec spec;
  spec.source = "--choose";
  spec.name = "choose";
  spec.output = choose.output;
  // The scenario is named even when it is the default: a case without one has none.
  spec.fixed.push_back({"scenario.plugin", whole.run.scenario, whole.run.scenario_source});
  for (const Setting& setting : settings)
    if (!is_frame_or_choice_key(setting.key) && setting.key != "scenario.plugin")
      spec.fixed.push_back({setting.key, setting.value, setting.source});
  spec.fixed.push_back({"duration", host::format_number(choice.duration), "choose.duration"});
  spec.work_precision.reference_integrator = choice.reference_integrator;
  const sweep::CaseSpec base = sweep::expand_cases(spec).at(0);
  if (dry_run) {
    check_creatable_folder(spec.output.parent_path(), "choose.output");
    out << "dry run: choose on " << whole.run.scenario << " at "
        << host::format_number(choice.frame_rate) << " Hz, " << candidates.size()
        << " candidate(s); results would go to " << spec.output.string()
        << "-ranked.csv; nothing run\n";
    return;
  }

  try {
    if (spec.output.has_parent_path())
      std::filesystem::create_directories(spec.output.parent_path());
    sweep::ResultsStore store(spec.output, false);
    store.set_metadata({{"name", "choose"},
                        {"frame_rate", choice.frame_rate},
                        {"T", choice.duration},
                        {"stretch_limit", choice.stretch_limit},
                        {"reference_stretch_factor", choice.reference_stretch_factor},
                        {"error_tolerance", choice.error_tolerance},
                        {"error_mesh", choice.error_mesh.empty() ? "same" : choice.error_mesh},
                        {"reference_integrator", choice.reference_integrator},
                        {"reference_substeps", choice.reference_substeps}});
    const std::filesystem::path cache_folder = choose.reference_cache.empty()
                                                   ? spec.output.parent_path() / "choose-references"
                                                   : std::filesystem::path(choose.reference_cache);
    sweep::TrajectoryCache cache(
        cache_folder, [&](const std::string& id) { return plugin_identity(search_path, id); },
        host_identity());
    CaseWorker worker(search_path);
    predict_local_solvers(candidates, base, choice.frame_rate, worker);
    const sweep::TrajectoryRunner runner = [&](const sweep::CaseSpec& c) {
      return run_sweep_trajectory(c, worker);
    };
    const std::vector<sweep::Choice> choices = sweep::choose_integrators(
        spec, base, candidates, choice, runner,
        [&](const sweep::CaseSpec& c) { return cache.run(runner, c); }, store, std::cerr);
    store.write_exports();

    nlohmann::ordered_json ranked;
    ranked["scene"] =
        base.key.empty() ? nlohmann::ordered_json(nullptr) : nlohmann::ordered_json(base.key);
    ranked["settings"] = {
        {"mesh", scene_mesh(whole.run)},
        {"frame_rate", choice.frame_rate},
        {"T", choice.duration},
        {"error_T", choice.error_duration > 0 ? choice.error_duration : choice.duration},
        {"stretch_limit", choice.stretch_limit},
        {"reference_stretch_factor", choice.reference_stretch_factor},
        {"error_tolerance", choice.error_tolerance},
        {"error_mesh", choice.error_mesh.empty() ? "same" : choice.error_mesh},
        {"unconverged", whole.run.unconverged_fails ? "fail" : "count"}};
    for (const sweep::Row& row : store.rows()) {
      if (row["kind"] == "reference") ranked["reference"] = row;
      if (row["kind"] == "precision_floor") ranked["precision_floor"] = row;
    }
    const std::vector<sweep::Row> rows = sweep::choice_rows(choices, choice);
    ranked["ranking"] = rows;
    const std::filesystem::path ranked_base = spec.output.string() + "-ranked";
    write_file_atomically(ranked_base.string() + ".json",
                          [&](std::ostream& file) { file << ranked.dump(2) << "\n"; });
    write_file_atomically(ranked_base.string() + ".csv",
                          [&](std::ostream& file) { file << sweep::rows_to_csv(rows); });

    const sweep::Row reference = ranked.value("reference", sweep::Row());
    out << "choose: " << whole.run.scenario << ", "
        << (whole.run.material ? "material " + whole.run.material->name
                               : std::string("per-spring values"))
        << ", " << host::format_number(choice.frame_rate)
        << " Hz, T = " << host::format_number(choice.duration)
        << " s; pass: stretch away from the pins <= " << host::format_number(choice.stretch_limit)
        << " x rest and its strain <= " << host::format_number(choice.reference_stretch_factor)
        << " x the reference's, error <= " << host::format_number(100 * choice.error_tolerance)
        << " % of the cloth diagonal"
        << " at T = "
        << host::format_number(choice.error_duration > 0 ? choice.error_duration : choice.duration)
        << " s"
        << (choice.error_mesh.empty() ? "" : " (error measured at " + choice.error_mesh + ")")
        << "\n  reference: " << sweep::reference_line(reference)
        << (cache.hits() > 0 ? " (from the cache " + cache_folder.string() + ")" : std::string())
        << "\n"
        << (ranked.contains("precision_floor")
                ? "  " + sweep::precision_floor_line(ranked["precision_floor"]) + "\n"
                : std::string())
        << sweep::choice_table(choices, choice) << "  results: " << ranked_base.string() << ".csv, "
        << ranked_base.string() << ".json (probes: " << store.csv_path().string() << ")\n";
  } catch (const sweep::SweepError& error) {
    throw host::InputError(error.what());
  }
}

}  // namespace clothlab::cli
