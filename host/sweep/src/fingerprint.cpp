#include "clothlab/sweep/fingerprint.hpp"

#include <clothlab/host/param_text.hpp>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <set>

#include "clothlab/sweep/sweep_error.hpp"

namespace clothlab::sweep {

Fingerprint sweep_fingerprint(const SweepSpec& spec, const PluginIdentity& plugin_identity) {
  Fingerprint fingerprint;
  fingerprint["mode"] = to_string(spec.mode);
  for (const Setting& setting : spec.fixed) fingerprint["setting." + setting.key] = setting.value;
  std::set<std::string> plugin_ids;
  for (const Axis& axis : spec.axes) {
    std::string values;
    for (const Setting& value : axis.values) {
      values += (values.empty() ? "" : ", ") + host::canonical_value(value.value);
      if (axis.key == "integrator.plugin" || axis.key == "scenario.plugin")
        plugin_ids.insert(value.value);
    }
    fingerprint["matrix." + axis.key] = "[" + values + "]";
  }
  for (const char* key : {"setting.integrator.plugin", "setting.scenario.plugin"}) {
    const auto fixed = fingerprint.find(key);
    if (fixed != fingerprint.end()) plugin_ids.insert(fixed->second);
  }
  if (spec.mode == SweepMode::WorkPrecision) {
    const auto& wp = spec.work_precision;
    fingerprint["work_precision.reference_integrator"] = wp.reference_integrator;
    plugin_ids.insert(wp.reference_integrator);
    std::string self;
    for (const std::string& id : wp.self_reference) self += (self.empty() ? "" : ", ") + id;
    fingerprint["work_precision.self_reference"] = "[" + self + "]";
    fingerprint["work_precision.refinement"] = host::format_number(wp.refinement);
    fingerprint["work_precision.dt_start"] = host::format_number(wp.dt_start);
    fingerprint["work_precision.levels"] = std::to_string(wp.levels);
  } else if (spec.mode == SweepMode::Stability) {
    const auto& st = spec.stability;
    fingerprint["find_max_dt.dt_min"] = host::format_number(st.dt_lower_limit);
    fingerprint["find_max_dt.dt_max"] = host::format_number(st.dt_upper_limit);
    fingerprint["find_max_dt.tolerance"] = host::format_number(st.relative_tolerance);
    fingerprint["find_max_dt.growth"] = host::format_number(st.growth);
    fingerprint["find_max_dt.max_evaluations"] = std::to_string(st.max_evaluations);
  }
  if (plugin_identity) {
    for (const std::string& id : plugin_ids) fingerprint["plugin." + id] = plugin_identity(id);
  }
  return fingerprint;
}

std::string describe_changes(const Fingerprint& before, const Fingerprint& after) {
  std::string changes;
  const auto add = [&](const std::string& name, const std::string& old_value,
                       const std::string& new_value) {
    changes += (changes.empty() ? "" : "; ") + name + " '" + old_value + "' -> '" + new_value + "'";
  };
  for (const auto& [name, value] : before) {
    const auto now = after.find(name);
    if (now == after.end()) {
      add(name, value, "(not set)");
    } else if (now->second != value) {
      add(name, value, now->second);
    }
  }
  for (const auto& [name, value] : after)
    if (!before.count(name)) add(name, "(not set)", value);
  return changes;
}

namespace {

constexpr uint64_t fnv1a_offset = 14695981039346656037ull;

uint64_t fnv1a(uint64_t hash, const char* bytes, std::size_t size) {
  for (std::size_t i = 0; i < size; ++i) {
    hash ^= static_cast<unsigned char>(bytes[i]);
    hash *= 1099511628211ull;
  }
  return hash;
}

std::string hex(uint64_t hash) {
  char text[17];
  std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(hash));
  return text;
}

}  // namespace

std::string file_hash(const std::string& path) {
  std::ifstream stream(path, std::ios::binary);
  if (!stream) throw SweepError(path + ": cannot read plugin file for the sweep fingerprint");
  uint64_t hash = fnv1a_offset;
  char buffer[1 << 16];
  while (stream.read(buffer, sizeof buffer) || stream.gcount() > 0)
    hash = fnv1a(hash, buffer, static_cast<std::size_t>(stream.gcount()));
  return hex(hash);
}

std::string text_hash(std::string_view text) {
  return hex(fnv1a(fnv1a_offset, text.data(), text.size()));
}

}  // namespace clothlab::sweep
