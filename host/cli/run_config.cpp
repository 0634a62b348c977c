#include "run_config.hpp"

#include <clothlab/host/errors.hpp>
#include <clothlab/host/param_text.hpp>
#include <cmath>
#include <optional>

namespace clothlab::cli {

namespace {

constexpr double max_dt_s = 10.0;
constexpr double max_duration_s = 1e6;
constexpr double max_steps = 1e9;
// More threads than this make libgomp fail with its own message on ordinary machines.
constexpr double max_threads = 256;
constexpr double max_timeout_s = 1e6;

// Validates host-owned values with the same parser and messages as plugin parameters.
double read_number(const Setting& setting, uint32_t type, double min_value, double max_value,
                   const char* unit, const std::string& allowed = {}) {
  clothlab_param_spec spec{};
  spec.struct_size = sizeof spec;
  spec.type = type;
  spec.min_value = min_value;
  spec.max_value = max_value;
  spec.unit = unit;
  const host::ParsedParam parsed = host::parse_param_text(spec, setting.value);
  const std::string problem = !parsed.value                          ? parsed.problem
                              : !host::in_range(spec, *parsed.value) ? "out of range"
                                                                     : std::string();
  if (!problem.empty())
    throw host::InputError(
        setting.source + ": " + setting.key + " = " + setting.value + ": " + problem +
        "; allowed: " + (allowed.empty() ? host::describe_allowed(spec) : allowed));
  return parsed.value->v[0];
}

// dt and duration must be > 0: the smallest positive double is the inclusive bound.
double read_positive(const Setting& setting, double max_value, const char* unit = "s") {
  return read_number(setting, CLOTHLAB_PARAM_REAL, std::nextafter(0.0, 1.0), max_value, unit,
                     "real in (0, " + host::format_number(max_value) + "]" +
                         (*unit ? std::string(" ") + unit : std::string()));
}

bool starts_with(const std::string& text, const std::string& prefix) {
  return text.size() > prefix.size() && text.compare(0, prefix.size(), prefix) == 0;
}

}  // namespace

RunConfig resolve_run_config(const std::vector<Setting>& settings) {
  RunConfig config;
  // The run length is a step count or a duration (default 2 s), whichever came last.
  bool length_is_duration = true;
  double duration = 2.0;
  std::optional<Setting> duration_setting;
  std::string bracket_source = "default find_max_dt bracket";  // the last of dt_min, dt_max set
  for (const Setting& setting : settings) {
    const std::string& key = setting.key;
    if (key == "integrator.plugin" || key == "scenario.plugin") {
      if (setting.value.empty())
        throw host::InputError(setting.source + ": " + key +
                               " is empty; allowed: a plugin name or path");
      const bool integrator = key == "integrator.plugin";
      (integrator ? config.integrator : config.scenario) = setting.value;
      (integrator ? config.integrator_source : config.scenario_source) = setting.source;
    } else if (key == "dt") {
      config.dt = read_positive(setting, max_dt_s);
    } else if (key == "steps") {
      config.steps =
          static_cast<uint64_t>(read_number(setting, CLOTHLAB_PARAM_INT, 1, max_steps, ""));
      length_is_duration = false;
    } else if (key == "duration") {
      duration = read_positive(setting, max_duration_s);
      length_is_duration = true;
      duration_setting = setting;
    } else if (key == "precision") {
      if (setting.value != "float32" && setting.value != "float64")
        throw host::InputError(setting.source + ": precision = " + setting.value +
                               ": unknown precision; allowed: float32, float64");
      config.float64 = setting.value == "float64";
    } else if (key == "threads") {
      config.threads =
          static_cast<int>(read_number(setting, CLOTHLAB_PARAM_INT, 0, max_threads, ""));
    } else if (key == "timeout") {
      config.timeout_s = read_positive(setting, max_timeout_s);
    } else if (key == "stability.interval") {
      config.stability_interval =
          static_cast<uint64_t>(read_number(setting, CLOTHLAB_PARAM_INT, 1, max_steps, "steps"));
    } else if (key == "stability.max_stretch") {
      config.max_stretch = read_number(setting, CLOTHLAB_PARAM_REAL, 1.0, 1e6, "");
    } else if (key == "stability.energy_margin") {
      config.energy_margin = read_positive(setting, 1e12, "");
    } else if (key == "find_max_dt.tolerance") {
      config.search_tolerance = read_number(setting, CLOTHLAB_PARAM_REAL, 1e-6, 1.0, "");
    } else if (key == "find_max_dt.dt_min") {
      config.search_dt_min = read_positive(setting, max_dt_s);
      bracket_source = setting.source;
    } else if (key == "find_max_dt.dt_max") {
      config.search_dt_max = read_positive(setting, max_dt_s);
      bracket_source = setting.source;
    } else if (starts_with(key, "integrator.")) {
      config.integrator_params.push_back({key.substr(11), setting.value, setting.source});
    } else if (starts_with(key, "scenario.")) {
      config.scenario_params.push_back({key.substr(9), setting.value, setting.source});
    } else if (starts_with(key, "plugin_params.") && key.find('.', 14) != std::string::npos) {
      config.plugin_params.push_back({key.substr(14), setting.value, setting.source});
    } else {
      throw host::InputError(setting.source + ": unknown key " + key +
                             "; valid: integrator, scenario, dt, steps, duration, precision, "
                             "threads, timeout, stability.interval, stability.max_stretch, "
                             "stability.energy_margin, find_max_dt.tolerance, find_max_dt.dt_min, "
                             "find_max_dt.dt_max, integrator.<parameter>, scenario.<parameter>, "
                             "plugin_params.<plugin id>.<parameter>");
    }
  }
  if (length_is_duration) {
    const double steps = std::round(duration / config.dt);
    if (steps < 1 || steps > max_steps) {
      const std::string source = duration_setting ? duration_setting->source : "default duration";
      throw host::InputError(source + ": duration = " + host::format_number(duration) +
                             " s at dt = " + host::format_number(config.dt) + " s gives " +
                             host::format_number(steps) + " steps; allowed: 1 to 1e9 steps");
    }
    config.steps = static_cast<uint64_t>(steps);
    config.duration = duration;
  } else {
    config.duration = static_cast<double>(config.steps) * config.dt;
  }
  if (config.search_dt_min >= config.search_dt_max)
    throw host::InputError(
        bracket_source + ": find_max_dt.dt_min = " + host::format_number(config.search_dt_min) +
        " s is not below find_max_dt.dt_max = " + host::format_number(config.search_dt_max) +
        " s; allowed: dt_min < dt_max");
  return config;
}

}  // namespace clothlab::cli
