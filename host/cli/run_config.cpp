#include "run_config.hpp"

#include <algorithm>
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

// frames.format: one name or a list "[vtp, obj]"; each once.
std::vector<std::string> read_frame_formats(const Setting& setting) {
  std::string text = setting.value;
  if (text.size() >= 2 && text.front() == '[' && text.back() == ']')
    text = text.substr(1, text.size() - 2);
  std::vector<std::string> formats;
  size_t begin = 0;
  while (begin <= text.size()) {
    size_t end = text.find(',', begin);
    if (end == std::string::npos) end = text.size();
    std::string name = text.substr(begin, end - begin);
    name.erase(0, name.find_first_not_of(' '));
    name.erase(name.find_last_not_of(' ') + 1);
    const bool known = name == "vtp" || name == "obj" || name == "pc2";
    if (!known || std::find(formats.begin(), formats.end(), name) != formats.end())
      throw host::InputError(setting.source + ": frames.format = " + setting.value + ": " +
                             (known ? "repeats " + name : "unknown format '" + name + "'") +
                             "; allowed: vtp, obj, pc2 or a list of them, e.g. [vtp, pc2]");
    formats.push_back(name);
    begin = end + 1;
  }
  return formats;
}

// Each material key with its allowed range; a material must set all of them.
struct MaterialKey {
  const char* key;
  double Material::*field;
  double min_value, max_value;
  const char* unit;
};
constexpr MaterialKey material_keys[] = {
    {"material.areal_density", &Material::areal_density, 1e-6, 1e3, "kg/m^2"},
    {"material.stretch_stiffness", &Material::stretch_stiffness, 1e-3, 1e8, "N/m"},
    {"material.shear_stiffness", &Material::shear_stiffness, 0.0, 1e8, "N/m"},
    {"material.bending_stiffness", &Material::bending_stiffness, 0.0, 1.0, "N m"},
    {"material.damping_time", &Material::damping_time, 0.0, 10.0, "s"},
};
constexpr double max_frame_rate_hz = 1e6;
constexpr double max_substeps = 1e6;

// Reads a material key into the material; false when the key is not one.
bool read_material_key(const Setting& setting, Material& material, std::vector<std::string>& seen) {
  if (setting.key == "material.name") {
    material.name = setting.value;
  } else {
    const MaterialKey* match = nullptr;
    for (const MaterialKey& candidate : material_keys)
      if (setting.key == candidate.key) match = &candidate;
    if (match == nullptr) return false;
    material.*(match->field) =
        read_number(setting, CLOTHLAB_PARAM_REAL, match->min_value, match->max_value, match->unit);
    seen.push_back(setting.key);
  }
  if (material.source.empty()) material.source = setting.source;
  return true;
}

void check_material_complete(const Material& material, const std::vector<std::string>& seen) {
  for (const MaterialKey& key : material_keys)
    if (std::find(seen.begin(), seen.end(), key.key) == seen.end())
      throw host::InputError(material.source + ": material " + material.name + " has no " +
                             key.key + "; allowed: real in [" + host::format_number(key.min_value) +
                             ", " + host::format_number(key.max_value) + "] " + key.unit +
                             " (a material sets every material.* value)");
  if (!(material.shear_stiffness < material.stretch_stiffness))
    throw host::InputError(material.source + ": material.shear_stiffness = " +
                           host::format_number(material.shear_stiffness) +
                           " N/m is not below material.stretch_stiffness = " +
                           host::format_number(material.stretch_stiffness) +
                           " N/m; allowed: shear < stretch (the grid's axes carry E - G)");
}

// "[a, b]" or "a" -> {"a", "b"}.
std::vector<std::string> word_list(const Setting& setting) {
  std::string text = setting.value;
  if (text.size() >= 2 && text.front() == '[' && text.back() == ']')
    text = text.substr(1, text.size() - 2);
  std::vector<std::string> words;
  std::string word;
  for (const char c : text + ",") {
    if (c == ',') {
      if (word.empty())
        throw host::InputError(setting.source + ": " + setting.key + " = " + setting.value +
                               ": empty name; allowed: a list of plugin names [a, b]");
      words.push_back(word);
      word.clear();
    } else if (c != ' ') {
      word += c;
    }
  }
  return words;
}

// ROWSxCOLS or N, each in [1, 4096].
std::string mesh_text(const Setting& setting) {
  const size_t cross = setting.value.find('x');
  const std::string rows = setting.value.substr(0, cross);
  const std::string cols = cross == std::string::npos ? rows : setting.value.substr(cross + 1);
  for (const std::string& part : {rows, cols}) {
    const Setting number{setting.key, part, setting.source};
    try {
      read_number(number, CLOTHLAB_PARAM_INT, 1, 4096, "");
    } catch (const host::InputError&) {
      throw host::InputError(setting.source + ": " + setting.key + " = " + setting.value +
                             ": not a mesh; allowed: ROWSxCOLS or N, each a whole number in "
                             "[1, 4096]");
    }
  }
  return rows + "x" + cols;
}

// choose.* keys into the choice settings; false when the key is not one.
bool read_choice_key(const Setting& setting, RunConfig& config) {
  sweep::ChoiceSettings& choice = config.choice;
  const std::string& key = setting.key;
  if (key == "choose.duration") {
    choice.duration = read_positive(setting, 1e3);
  } else if (key == "choose.probe_timeout") {
    choice.probe_timeout_s = read_positive(setting, 1e6);
  } else if (key == "choose.stop_factor") {
    // Below 2 the budget could stop a setting cheaper than the best (integrator_choice.hpp).
    const char* allowed = "0 (no cost budget) or a real in [2, 1000]";
    choice.stop_factor = read_number(setting, CLOTHLAB_PARAM_REAL, 0, 1e3, "", allowed);
    if (choice.stop_factor > 0 && choice.stop_factor < 2)
      throw host::InputError(setting.source + ": " + key + " = " + setting.value +
                             ": out of range; allowed: " + allowed);
  } else if (key == "choose.error_duration") {
    choice.error_duration = read_positive(setting, 1e3);
  } else if (key == "choose.stretch_limit") {
    choice.stretch_limit = read_number(setting, CLOTHLAB_PARAM_REAL, 1.0, 1e6, "x rest length");
  } else if (key == "choose.error_tolerance") {
    choice.error_tolerance = read_positive(setting, 1.0, "of the cloth diagonal");
  } else if (key == "choose.max_substeps") {
    choice.max_substeps =
        static_cast<uint32_t>(read_number(setting, CLOTHLAB_PARAM_INT, 1, max_substeps, ""));
  } else if (key == "choose.max_iterations") {
    choice.max_iterations =
        static_cast<uint32_t>(read_number(setting, CLOTHLAB_PARAM_INT, 1, 1e5, ""));
  } else if (key == "choose.reference_substeps") {
    choice.reference_substeps =
        static_cast<uint32_t>(read_number(setting, CLOTHLAB_PARAM_INT, 1, max_substeps, ""));
  } else if (key == "choose.reference_integrator") {
    choice.reference_integrator = word_list(setting).at(0);
  } else if (key == "choose.error_mesh") {
    choice.error_mesh = mesh_text(setting);
  } else if (key == "choose.integrators") {
    config.choice_integrators = word_list(setting);
  } else if (key == "choose.output") {
    config.choice_output = setting.value;
  } else if (key == "choose.reference_cache") {
    if (setting.value.empty())
      throw host::InputError(setting.source +
                             ": choose.reference_cache is empty; allowed: a folder path");
    config.choice_reference_cache = setting.value;
  } else {
    return false;
  }
  return true;
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
  std::optional<Setting> dt_setting, frame_rate_setting, substeps_setting;
  Material material;
  std::vector<std::string> material_keys_seen;
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
      dt_setting = setting;
    } else if (key == "frame_rate") {
      config.frame_rate = read_positive(setting, max_frame_rate_hz, "Hz");
      frame_rate_setting = setting;
    } else if (key == "substeps") {
      config.substeps = static_cast<uint64_t>(
          read_number(setting, CLOTHLAB_PARAM_INT, 1, max_substeps, "steps per frame"));
      substeps_setting = setting;
    } else if (read_material_key(setting, material, material_keys_seen)) {
    } else if (read_choice_key(setting, config)) {
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
    } else if (key == "frames.dir") {
      if (setting.value.empty())
        throw host::InputError(setting.source + ": frames.dir is empty; allowed: a folder path");
      config.frames.dir = setting.value;
    } else if (key == "frames.every") {
      config.frames.every =
          static_cast<uint64_t>(read_number(setting, CLOTHLAB_PARAM_INT, 1, max_steps, "steps"));
    } else if (key == "frames.rate") {
      config.frames.rate = read_positive(setting, 1e6, "Hz");
      config.frames.every.reset();
    } else if (key == "frames.format") {
      config.frames.formats = read_frame_formats(setting);
    } else if (starts_with(key, "integrator.")) {
      config.integrator_params.push_back({key.substr(11), setting.value, setting.source});
    } else if (starts_with(key, "scenario.")) {
      config.scenario_params.push_back({key.substr(9), setting.value, setting.source});
    } else if (starts_with(key, "plugin_params.") && key.find('.', 14) != std::string::npos) {
      config.plugin_params.push_back({key.substr(14), setting.value, setting.source});
    } else {
      throw host::InputError(setting.source + ": unknown key " + key +
                             "; valid: integrator, scenario, dt, frame_rate, substeps, steps, "
                             "duration, precision, threads, timeout, material.name, "
                             "material.areal_density, material.stretch_stiffness, "
                             "material.shear_stiffness, material.bending_stiffness, "
                             "material.damping_time, choose.duration, choose.error_duration, "
                             "choose.probe_timeout, choose.stop_factor, choose.stretch_limit, "
                             "choose.error_tolerance, choose.max_substeps, choose.max_iterations, "
                             "choose.reference_substeps, choose.reference_integrator, "
                             "choose.error_mesh, choose.integrators, choose.output, "
                             "choose.reference_cache, "
                             "stability.interval, stability.max_stretch, "
                             "stability.energy_margin, find_max_dt.tolerance, find_max_dt.dt_min, "
                             "find_max_dt.dt_max, frames.dir, frames.every, frames.rate, "
                             "frames.format, integrator.<parameter>, scenario.<parameter>, "
                             "plugin_params.<plugin id>.<parameter>");
    }
  }
  if (!material.source.empty()) {
    check_material_complete(material, material_keys_seen);
    config.material = material;
  }
  if (frame_rate_setting) {
    if (dt_setting)
      throw host::InputError(dt_setting->source + ": dt = " + dt_setting->value +
                             " conflicts with " + frame_rate_setting->source +
                             ": frame_rate = " + frame_rate_setting->value +
                             "; allowed: dt, or frame_rate and substeps (dt = 1 / (frame_rate "
                             "substeps)), not both");
    config.dt = 1.0 / (config.frame_rate * static_cast<double>(config.substeps));
    config.choice.frame_rate = config.frame_rate;
  } else if (substeps_setting) {
    throw host::InputError(substeps_setting->source + ": substeps = " + substeps_setting->value +
                           " without frame_rate; allowed: substeps together with frame_rate "
                           "(Hz)");
  } else {
    config.frame_rate = 1.0 / config.dt;
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
  // A frame every 1/rate s of simulated time, to the nearest step (at least every step); the
  // rate is frames.rate, else the frame_rate the run was set up with, else 60 Hz.
  const double frames_rate = config.frames.rate   ? *config.frames.rate
                             : frame_rate_setting ? config.frame_rate
                                                  : 60.0;
  config.frames.every_steps =
      config.frames.every
          ? *config.frames.every
          : static_cast<uint64_t>(std::max(1.0, std::round(1.0 / (frames_rate * config.dt))));
  if (config.search_dt_min >= config.search_dt_max)
    throw host::InputError(
        bracket_source + ": find_max_dt.dt_min = " + host::format_number(config.search_dt_min) +
        " s is not below find_max_dt.dt_max = " + host::format_number(config.search_dt_max) +
        " s; allowed: dt_min < dt_max");
  return config;
}

}  // namespace clothlab::cli
