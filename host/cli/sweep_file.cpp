#include "sweep_file.hpp"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <clothlab/config/yaml_settings.hpp>
#include <clothlab/host/errors.hpp>
#include <clothlab/host/param_text.hpp>
#include <clothlab/sweep/sweep_error.hpp>
#include <set>

#include "run_config.hpp"
#include "run_keys.hpp"

namespace clothlab::cli {
namespace {

[[noreturn]] void fail(const std::string& source, const YAML::Node& node, const std::string& key,
                       const std::string& value, const std::string& allowed) {
  throw sweep::SweepError(config::location(source, node.Mark()) + ": " + key + " = '" + value +
                          "': allowed " + allowed);
}

std::string item_text(const std::string& source, const YAML::Node& node, const std::string& key) {
  if (node.IsScalar()) return node.Scalar();
  if (node.IsSequence()) {
    std::string text = "[";
    for (std::size_t i = 0; i < node.size(); ++i) {
      if (!node[i].IsScalar()) fail(source, node[i], key, "(nested)", "plain values in a list");
      text += (i > 0 ? ", " : "") + node[i].Scalar();
    }
    return text + "]";
  }
  fail(source, node, key, "(empty)", "a value or a list of plain values");
}

// One axis: its values in file order, each once, each with its own place in the file and
// checked by the key table as the case's setting it becomes.
sweep::Axis read_axis(const std::string& source, const std::string& name, const YAML::Node& node) {
  sweep::Axis axis{config::canonical_key(name), {}};
  const std::string key = "sweep.matrix." + name;
  const auto add = [&](const YAML::Node& item) {
    axis.values.push_back(
        {axis.key, item_text(source, item, key), config::location(source, item.Mark())});
  };
  if (node.IsScalar()) {
    add(node);
  } else if (node.IsSequence() && node.size() > 0) {
    for (const YAML::Node& item : node) add(item);
  } else {
    fail(source, node, key, "(empty)", "a value or a non-empty list of values");
  }
  std::set<std::string> seen;
  for (std::size_t i = 0; i < axis.values.size(); ++i) {
    const Setting& value = axis.values[i];
    const KeyInfo* info = find_run_key(value.key);
    if (info == nullptr) throw host::InputError(unknown_key_message(value));
    check_value(*info, value);
    if (!seen.insert(host::canonical_value(value.value)).second)
      fail(source, node.IsSequence() ? node[i] : node, key, value.value, "each value once");
  }
  return axis;
}

// The file says how long every case runs, once; the command line may change it.
void check_length(const std::string& source, const std::vector<Setting>& file,
                  const YAML::Node& root) {
  const auto has = [&](const char* key) {
    return std::any_of(file.begin(), file.end(),
                       [&](const Setting& setting) { return setting.key == key; });
  };
  if (has("steps") && has("duration"))
    fail(source, root, "steps/duration", "both", "one of steps or duration");
  if (!has("steps") && !has("duration"))
    fail(source, root, "steps/duration", "(missing)", "one of steps or duration at the top level");
}

void check_mode_axes(const std::string& source, const YAML::Node& matrix,
                     const sweep::SweepSpec& spec) {
  const auto has_axis = [&](const char* key) {
    return std::any_of(spec.axes.begin(), spec.axes.end(),
                       [&](const sweep::Axis& axis) { return axis.key == key; });
  };
  const auto has_fixed = [&](const char* key) {
    return std::any_of(spec.fixed.begin(), spec.fixed.end(),
                       [&](const Setting& setting) { return setting.key == key; });
  };
  const auto has = [&](const char* key) { return has_axis(key) || has_fixed(key); };
  if (spec.mode == sweep::SweepMode::Run && !has("dt") && !has("frame_rate"))
    fail(source, matrix, "sweep.matrix.dt", "(missing)",
         "a dt or frame_rate list (or a fixed one) in run mode");
  if (spec.mode != sweep::SweepMode::Run && has_axis("dt"))
    fail(source, matrix, "sweep.matrix.dt", "(a list)",
         std::string("no dt axis in ") + sweep::to_string(spec.mode) +
             " mode (it chooses dt itself)");
  // The searches and ladders set dt for each probe, which a frame rate would contradict.
  for (const char* key : {"frame_rate", "substeps"})
    if (spec.mode != sweep::SweepMode::Run && has(key))
      fail(source, matrix, key, "(set)",
           std::string("no ") + key + " in " + sweep::to_string(spec.mode) +
               " mode (it chooses dt itself)");
  if (!has_axis("integrator.plugin"))
    fail(source, matrix, "sweep.matrix.integrator", "(missing)", "a list of integrator ids");
}

}  // namespace

sweep::SweepSpec parse_sweep(const std::string& yaml_text, const std::string& source,
                             const std::vector<Setting>& overrides) {
  return parse_sweep(config::load_yaml_text(yaml_text, source), source, overrides);
}

sweep::SweepSpec parse_sweep(const YAML::Node& root, const std::string& source,
                             const std::vector<Setting>& overrides) {
  if (!root.IsMap()) fail(source, root, "(document)", "(not a map)", "a map of settings");
  const YAML::Node section = root["sweep"];
  if (!section || !section.IsMap()) fail(source, root, "sweep", "(missing)", "a sweep: section");
  const YAML::Node matrix = section["matrix"];
  if (!matrix) fail(source, section, "sweep.matrix", "(missing)", "a map of key: [values]");
  if (!matrix.IsMap())
    fail(source, matrix, "sweep.matrix", "(not a map)", "a map of key: [values]");

  // The one flattener checks the whole file (repeated keys, empty maps, bounds).
  std::vector<Setting> file;
  for (Setting& setting : config::flatten_settings(root, source))
    if (!setting.key.starts_with("sweep.matrix.")) file.push_back(std::move(setting));
  check_length(source, file, root);

  sweep::SweepSpec spec;
  spec.source = source;
  for (const auto& entry : matrix)
    spec.axes.push_back(read_axis(source, config::key_text(entry.first, source), entry.second));
  for (const Setting& setting : overrides)
    for (const sweep::Axis& axis : spec.axes)
      if (setting.key == axis.key)
        throw host::InputError(setting.source + ": " + setting.key + " = " + setting.value +
                               ": the matrix of " + source +
                               " sets it; allowed: a key the matrix does not set");

  // The command line's settings come after the file's and win. The key table checks them all,
  // with the matrix's first case, so that keys that go together (dt, frame_rate, substeps) are
  // checked together; every other case is checked before the first runs (sweep_mode.cpp).
  std::vector<Setting> settings = file;
  settings.insert(settings.end(), overrides.begin(), overrides.end());
  std::vector<Setting> first_case = settings;
  for (const sweep::Axis& axis : spec.axes) first_case.push_back(axis.values.front());
  const Configuration whole = resolve_configuration(first_case);

  // sweep.* and slurm.* describe the sweep, not a case: a case sees the other keys.
  for (const Setting& setting : settings)
    if (!setting.key.starts_with("sweep.") && !setting.key.starts_with("slurm."))
      spec.fixed.push_back(setting);
  if (whole.sweep.name.empty()) fail(source, section, "sweep.name", "(missing)", "[a-z0-9_-]+");
  spec.name = whole.sweep.name;
  spec.mode = whole.sweep.mode;
  spec.output = whole.sweep.output.empty() ? std::filesystem::path("results") / spec.name
                                           : std::filesystem::path(whole.sweep.output);
  spec.work_precision = whole.sweep.work_precision;
  spec.stability = whole.find_max_dt;
  // The first probe of a search is the run's dt, as with --find-max-dt (or the predicted limit).
  spec.stability.dt_initial =
      std::clamp(whole.run.dt, spec.stability.dt_lower_limit, spec.stability.dt_upper_limit);
  spec.slurm = whole.sweep.slurm;
  check_mode_axes(source, matrix, spec);
  return spec;
}

sweep::SweepSpec load_sweep(const std::filesystem::path& path,
                            const std::vector<Setting>& overrides) {
  return parse_sweep(config::load_yaml_file(path), path.string(), overrides);
}

bool is_sweep_file(const std::filesystem::path& path) {
  try {
    const YAML::Node root = config::load_yaml_file(path);
    return root.IsMap() && root["sweep"];
  } catch (const host::InputError&) {
    return false;  // reading it as a single-run config reports the problem
  }
}

}  // namespace clothlab::cli
