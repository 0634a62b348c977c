#include "max_dt_search.hpp"

#include <clothlab/analysis/find_max_dt.hpp>
#include <clothlab/sweep/progress.hpp>
#include <cmath>
#include <cstdio>
#include <exception>
#include <iostream>

#include "case_execution.hpp"
#include "isolation.hpp"

namespace clothlab::cli {

namespace {

RunConfig with_dt(RunConfig config, double dt) {
  config.dt = dt;
  config.steps = static_cast<uint64_t>(std::max(1.0, std::round(config.duration / dt)));
  return config;
}

// "dt 0.00125 s: stable", "dt 0.0025 s: unstable (energy at step 12)".
std::string probe_label(const nlohmann::json& probe) {
  char dt[32];
  std::snprintf(dt, sizeof dt, "%.4g", probe["dt"].get<double>());
  std::string label = "dt " + std::string(dt) + " s: ";
  if (probe["stable"].get<bool>()) return label + "stable";
  const nlohmann::json& check = probe["failed_check"];
  label += "unstable (" + (check.is_string() ? check.get<std::string>() : std::string("?"));
  if (probe["failed_step"].is_number())
    label += " at step " + std::to_string(probe["failed_step"].get<uint64_t>());
  return label + ")";
}

}  // namespace

nlohmann::json find_max_dt(const Configuration& whole, const host::PluginSearchPath& search_path,
                           bool show_progress) {
  const RunConfig& config = whole.run;
  // Every probe below turns an error into an unstable run, so bad input is found first.
  check_plugins(config, search_path);
  analysis::MaxDtOptions options = whole.find_max_dt;
  nlohmann::json result;
  result["duration"] = config.duration;
  result["tolerance"] = options.relative_tolerance;
  result["predicted_dt_max"] = nullptr;
  options.dt_initial = std::clamp(config.dt, options.dt_lower_limit, options.dt_upper_limit);
  try {
    const nlohmann::json prediction =
        run_isolated([&] { return predict_case(config, search_path); }, config.timeout_s);
    result["predicted_dt_max"] = prediction["dt_max"];
    result["omega_max"] = prediction["omega_max"];
    result["dominant_eigenvalue"] = {prediction["dominant_re"], prediction["dominant_im"]};
    // The prediction is the natural first probe: the bracket is then found in a step or two.
    if (prediction["dt_max"].is_number())
      options.dt_initial = std::clamp(prediction["dt_max"].get<double>(), options.dt_lower_limit,
                                      options.dt_upper_limit);
  } catch (const std::exception& error) {
    result["prediction_error"] = error.what();
  }

  nlohmann::json probes = nlohmann::json::array();
  sweep::Progress progress(static_cast<std::size_t>(options.max_evaluations), 0, std::cerr,
                           show_progress);
  const analysis::MaxDtResult search = analysis::find_max_dt(
      [&](double dt) {
        nlohmann::json probe = {{"dt", dt}};
        try {
          const host::RunSummary run =
              case_run_from_json(
                  run_isolated([&] { return run_case(with_dt(config, dt), search_path); },
                               config.timeout_s))
                  .summary;
          result["integrator"] = run.integrator;
          result["scenario"] = run.scenario;
          result["rows"] = run.rows;
          result["cols"] = run.cols;
          result["precision"] = run.precision;
          probe["stable"] = run.stable;
          probe["failed_check"] = run.failed_check ? nlohmann::json(*run.failed_check) : nullptr;
          probe["failed_step"] = run.failed_step ? nlohmann::json(*run.failed_step) : nullptr;
        } catch (const std::exception& error) {
          probe["stable"] = false;
          probe["failed_check"] = "error";
          probe["error"] = error.what();
        }
        probes.push_back(probe);
        progress.case_finished(probe_label(probe));
        return probe["stable"].get<bool>();
      },
      options);
  progress.finish();
  result["dt_max"] = search.dt_stable > 0 ? nlohmann::json(search.dt_stable) : nullptr;
  result["dt_unstable"] = search.dt_unstable > 0 ? nlohmann::json(search.dt_unstable) : nullptr;
  result["outcome"] = analysis::to_string(search.outcome);
  result["evaluations"] = search.evaluations;
  result["measured_over_predicted"] =
      result["predicted_dt_max"].is_number() && search.dt_stable > 0
          ? nlohmann::json(search.dt_stable / result["predicted_dt_max"].get<double>())
          : nullptr;
  result["probes"] = probes;
  return result;
}

std::string max_dt_summary(const nlohmann::json& result) {
  auto number = [](const nlohmann::json& value) {
    if (!value.is_number()) return std::string("-");
    char text[32];
    std::snprintf(text, sizeof text, "%.4g", value.get<double>());
    return std::string(text);
  };
  std::string text = result.value("integrator", std::string("?")) + " on " +
                     result.value("scenario", std::string("?")) + " " +
                     number(result.value("rows", nlohmann::json())) + "x" +
                     number(result.value("cols", nlohmann::json())) + ", " +
                     result.value("precision", std::string("?")) + ", " +
                     number(result["duration"]) + " s simulated:\n";
  text += "  measured  dt_max = " + number(result["dt_max"]) + " s (unstable at " +
          number(result["dt_unstable"]) + " s; " + result["outcome"].get<std::string>() + ", " +
          std::to_string(result["evaluations"].get<int>()) + " runs, tolerance " +
          number(result["tolerance"]) + ")\n";
  text += "  predicted dt_max = " + number(result["predicted_dt_max"]) +
          " s (linearised at rest, with damping)";
  if (result.contains("prediction_error"))
    text += ": " + result["prediction_error"].get<std::string>();
  text += "\n  measured / predicted = " + number(result["measured_over_predicted"]) + "\n";
  return text;
}

}  // namespace clothlab::cli
