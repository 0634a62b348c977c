#include "case_execution.hpp"

#include <clothlab/analysis/stability_prediction.hpp>
#include <cmath>

#include "run_report.hpp"
#include "simulation.hpp"

namespace clothlab::cli {

nlohmann::json run_case(const RunConfig& config, const host::PluginSearchPath& search_path,
                        bool with_positions) {
  Simulation simulation(config, search_path);
  const RunRecord record = simulation.run();
  nlohmann::json json = summary_json(record);
  if (with_positions) {
    std::vector<double> positions;
    simulation.cloth().positions(positions);
    json["positions"] = positions;
    const Scene& scene = simulation.cloth().scene();
    json["diagonal"] = std::hypot(scene.width, scene.height);
  }
  return json;
}

nlohmann::json predict_case(const RunConfig& config, const host::PluginSearchPath& search_path) {
  const Simulation simulation(config, search_path);
  const analysis::Method method = analysis::method_for_plugin(simulation.integrator_id().c_str());
  analysis::VerletDamping verlet;
  const nlohmann::json& params = simulation.integrator_params();
  if (method == analysis::Method::PositionVerlet) {
    verlet.rate_per_s = params.value("damping", 0.0);
    verlet.per_step_fraction = params.value("damping_per_step", 0.0);
  }
  const analysis::StabilityPrediction prediction =
      analysis::predict_stability(simulation.cloth().scene(), method, verlet, config.threads);
  nlohmann::json json;
  json["method"] = analysis::to_string(method);
  json["dt_max"] = std::isfinite(prediction.dt_max) ? nlohmann::json(prediction.dt_max)
                                                    : nlohmann::json(nullptr);
  json["omega_max"] = prediction.spectrum.omega_max;
  json["dominant_re"] = prediction.spectrum.dominant_eigenvalue.real();
  json["dominant_im"] = prediction.spectrum.dominant_eigenvalue.imag();
  return json;
}

}  // namespace clothlab::cli
