#include "case_execution.hpp"

#include <clothlab/ext/integrator_traits.h>

#include <clothlab/analysis/local_solve_bound.hpp>
#include <clothlab/analysis/stability_prediction.hpp>
#include <clothlab/core/triangle_mesh.hpp>
#include <cmath>
#include <stdexcept>

#include "isolation.hpp"
#include "run_report.hpp"
#include "simulation.hpp"

namespace clothlab::cli {

nlohmann::json run_case(const RunConfig& config, const host::PluginSearchPath& search_path,
                        bool with_positions) {
  return run_case(config, load_plugins(config, search_path), with_positions);
}

nlohmann::json run_case(const RunConfig& config, LoadedPlugins plugins, bool with_positions) {
  Simulation simulation(config, std::move(plugins));
  nlohmann::json answer = {{"summary", summary_json(simulation.run())}};
  if (with_positions) {
    std::vector<double> positions;
    simulation.cloth().positions(positions);
    answer["positions"] = positions;
    answer["diagonal"] = rest_diagonal(simulation.cloth().scene(), *simulation.cloth().model());
  }
  return answer;
}

CaseRun case_run_from_json(const nlohmann::json& answer) {
  CaseRun run;
  run.summary = host::run_summary_from_json(answer.at("summary"), "the case worker's answer");
  // A diverged run's non-finite positions are JSON nulls; its verdict says enough.
  if (answer.contains("positions") && run.summary.stable)
    run.positions = answer["positions"].get<std::vector<double>>();
  if (answer.contains("diagonal")) run.diagonal = answer["diagonal"].get<double>();
  return run;
}

nlohmann::json predict_case(const RunConfig& config, const host::PluginSearchPath& search_path) {
  return predict_case(config, load_plugins(config, search_path));
}

nlohmann::json predict_case(const RunConfig& config, LoadedPlugins plugins) {
  const Simulation simulation(config, std::move(plugins));
  const host::IntegratorPlugin& integrator = simulation.integrator();
  const void* declared = integrator.extension(CLOTHLAB_EXT_EXPLICIT_SCHEME);
  if (declared == nullptr) {
    throw std::invalid_argument("integrator " + simulation.integrator_id() +
                                " declares no explicit scheme (" CLOTHLAB_EXT_EXPLICIT_SCHEME
                                "): no stability prediction");
  }
  const analysis::RknTable table =
      analysis::rkn_table(*static_cast<const clothlab_explicit_scheme*>(declared));
  const analysis::StabilityPrediction prediction = analysis::predict_stability(
      simulation.cloth().scene(), table, integrator.uses_velocity_forces(), config.threads);
  nlohmann::json json;
  json["method"] = "declared scheme: " + std::to_string(table.stages) + " stages, " +
                   std::to_string(table.evaluations_per_step()) + " evaluations per step";
  json["evals_per_step"] = table.evaluations_per_step();
  json["dt_max"] = std::isfinite(prediction.dt_max) ? nlohmann::json(prediction.dt_max)
                                                    : nlohmann::json(nullptr);
  json["omega_max"] = prediction.spectrum.omega_max;
  json["dominant_re"] = prediction.spectrum.dominant_eigenvalue.real();
  json["dominant_im"] = prediction.spectrum.dominant_eigenvalue.imag();
  return json;
}

nlohmann::json local_solve_case(const RunConfig& config, LoadedPlugins plugins) {
  const auto* traits = static_cast<const clothlab_integrator_traits*>(
      plugins.integrator->extension(CLOTHLAB_EXT_INTEGRATOR_TRAITS));
  if (traits == nullptr || traits->struct_size < sizeof(clothlab_integrator_traits) ||
      (traits->flags & CLOTHLAB_TRAIT_LOCAL_SOLVES) == 0)
    return nullptr;
  const Simulation simulation(config, std::move(plugins));
  const analysis::LocalSolveBound bound = analysis::local_solve_bound(*simulation.cloth().model());
  nlohmann::json json;
  json["dt_max"] =
      std::isfinite(bound.dt_max) ? nlohmann::json(bound.dt_max) : nlohmann::json(nullptr);
  json["particle_mass"] = bound.particle_mass;
  json["stiffness"] = bound.stiffness;
  return json;
}

void check_plugins(const RunConfig& config, const host::PluginSearchPath& search_path) {
  run_isolated(
      [&] {
        load_plugins(config, search_path);
        return nlohmann::json();
      },
      config.timeout_s);
}

}  // namespace clothlab::cli
