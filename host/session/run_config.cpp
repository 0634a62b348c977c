#include "run_config.hpp"

#include <algorithm>
#include <clothlab/host/errors.hpp>
#include <clothlab/host/param_text.hpp>
#include <cmath>

#include "last_setting.hpp"
#include "run_keys.hpp"

namespace clothlab::cli {

const Setting* last_setting(const std::vector<Setting>& settings, const std::string& key) {
  const auto found = std::find_if(settings.rbegin(), settings.rend(),
                                  [&](const Setting& setting) { return setting.key == key; });
  return found == settings.rend() ? nullptr : &*found;
}

std::string where_set(const std::vector<Setting>& settings, const std::string& key) {
  const Setting* setting = last_setting(settings, key);
  return setting == nullptr ? key : setting->source + ": " + key;
}

namespace {

// A material sets every material.* number (the keys of the table's material family).
void check_material_complete(const Material& material, const std::vector<Setting>& settings) {
  for (const KeyInfo& info : run_keys())
    if (std::string_view(info.key).starts_with("material.") && info.type == KeyType::Real &&
        last_setting(settings, info.key) == nullptr)
      throw host::InputError(material.source + ": material " + material.name + " has no " +
                             info.key + "; allowed: " + describe_allowed(info) +
                             " (a material sets every material.* value)");
  if (!(material.shear_stiffness < material.stretch_stiffness))
    throw host::InputError(material.source + ": material.shear_stiffness = " +
                           host::format_number(material.shear_stiffness) +
                           " N/m is not below material.stretch_stiffness = " +
                           host::format_number(material.stretch_stiffness) +
                           " N/m; allowed: shear < stretch (the grid's axes carry E - G)");
}

}  // namespace

Configuration resolve_configuration(const std::vector<Setting>& settings) {
  Configuration whole;
  for (const KeyInfo& info : run_keys())
    if (info.default_value)
      info.apply(whole, check_value(info, {info.key, info.default_value,
                                           std::string("default ") + info.key}));
  for (const Setting& setting : settings) {
    const KeyInfo* info = find_run_key(setting.key);
    if (info == nullptr) throw host::InputError(unknown_key_message(setting));
    info->apply(whole, check_value(*info, setting));
  }
  RunConfig& config = whole.run;

  if (config.material) check_material_complete(*config.material, settings);
  const Setting* dt = last_setting(settings, "dt");
  const Setting* frame_rate = last_setting(settings, "frame_rate");
  if (frame_rate) {
    if (dt)
      throw host::InputError(dt->source + ": dt = " + dt->value + " conflicts with " +
                             frame_rate->source + ": frame_rate = " + frame_rate->value +
                             "; allowed: dt, or frame_rate and substeps (dt = 1 / (frame_rate "
                             "substeps)), not both");
    config.dt = 1.0 / (config.frame_rate * static_cast<double>(config.substeps));
    whole.choose.search.frame_rate = config.frame_rate;
  } else if (const Setting* substeps = last_setting(settings, "substeps")) {
    throw host::InputError(substeps->source + ": substeps = " + substeps->value +
                           " without frame_rate; allowed: substeps together with frame_rate "
                           "(Hz)");
  } else {
    config.frame_rate = 1.0 / config.dt;
  }

  // The run length is a step count or a duration, whichever came last.
  const auto length = std::find_if(settings.rbegin(), settings.rend(), [](const Setting& s) {
    return s.key == "steps" || s.key == "duration";
  });
  if (length != settings.rend() && length->key == "steps") {
    config.duration = static_cast<double>(config.steps) * config.dt;
  } else {
    const KeyInfo& steps_key = *find_run_key("steps");
    const double steps = std::round(config.duration / config.dt);
    if (steps < steps_key.min_value || steps > steps_key.max_value) {
      const std::string source = length != settings.rend() ? length->source : "default duration";
      throw host::InputError(source + ": duration = " + host::format_number(config.duration) +
                             " s at dt = " + host::format_number(config.dt) + " s gives " +
                             host::format_number(steps) +
                             " steps; allowed: " + describe_allowed(steps_key) + " steps");
    }
    config.steps = static_cast<uint64_t>(steps);
  }

  // A frame every 1/rate s of simulated time, to the nearest step (at least every step); the
  // rate is frames.rate, else the frame_rate the run was set up with, else 60 Hz.
  const double frames_rate = config.frames.rate ? *config.frames.rate
                             : frame_rate       ? config.frame_rate
                                                : 60.0;
  config.frames.every_steps =
      config.frames.every
          ? *config.frames.every
          : static_cast<uint64_t>(std::max(1.0, std::round(1.0 / (frames_rate * config.dt))));

  const analysis::MaxDtOptions& search = whole.find_max_dt;
  if (search.dt_lower_limit >= search.dt_upper_limit) {
    const auto bracket = std::find_if(settings.rbegin(), settings.rend(), [](const Setting& s) {
      return s.key == "find_max_dt.dt_min" || s.key == "find_max_dt.dt_max";
    });
    const std::string source = bracket != settings.rend() ? bracket->source : "default";
    throw host::InputError(
        source + ": find_max_dt.dt_min = " + host::format_number(search.dt_lower_limit) +
        " s is not below find_max_dt.dt_max = " + host::format_number(search.dt_upper_limit) +
        " s; allowed: dt_min < dt_max");
  }
  return whole;
}

RunConfig resolve_run_config(const std::vector<Setting>& settings) {
  return resolve_configuration(settings).run;
}

void refuse_sweep_settings(const std::vector<Setting>& settings) {
  for (const Setting& setting : settings)
    if (setting.key.starts_with("sweep.") || setting.key.starts_with("slurm."))
      throw host::InputError(setting.source + ": " + setting.key +
                             " is a sweep's setting; allowed: in a sweep file (one "
                             "with a sweep: section) or on its command line");
}

}  // namespace clothlab::cli
