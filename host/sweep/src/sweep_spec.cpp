#include "clothlab/sweep/sweep_spec.hpp"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <charconv>
#include <clothlab/config/yaml_settings.hpp>
#include <clothlab/host/errors.hpp>
#include <clothlab/host/identifiers.hpp>
#include <clothlab/host/param_text.hpp>
#include <cmath>
#include <functional>
#include <set>

#include "clothlab/sweep/sweep_error.hpp"

namespace clothlab::sweep {
namespace {

std::string location(const std::string& source, const YAML::Node& node) {
  return config::location(source, node.Mark());
}

[[noreturn]] void fail(const std::string& source, const YAML::Node& node, const std::string& key,
                       const std::string& value, const std::string& allowed) {
  throw SweepError(location(source, node) + ": " + key + " = '" + value + "': allowed " + allowed);
}

std::string scalar_text(const std::string& source, const YAML::Node& node, const std::string& key) {
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

double number(const std::string& source, const YAML::Node& node, const std::string& key, double low,
              double high, const std::string& allowed) {
  const std::string text = node.IsScalar() ? node.Scalar() : "(not a value)";
  const auto value = host::parse_real(text);
  if (!value || *value < low || *value > high) fail(source, node, key, text, allowed);
  return *value;
}

double whole_number(const std::string& source, const YAML::Node& node, const std::string& key,
                    double low, double high) {
  const std::string allowed =
      "a whole number in [" + host::format_number(low) + ", " + host::format_number(high) + "]";
  const double value = number(source, node, key, low, high, allowed);
  if (value != std::floor(value)) fail(source, node, key, node.Scalar(), allowed);
  return value;
}

// Visits each key of a section, rejecting keys not in `allowed`.
void for_each_key(const std::string& source, const YAML::Node& section, const std::string& name,
                  const std::vector<std::string>& allowed,
                  const std::function<void(const std::string&, const YAML::Node&)>& visit) {
  if (!section.IsMap()) fail(source, section, name, "(not a map)", "a map of keys");
  for (const auto& entry : section) {
    const std::string key = config::key_text(entry.first, source);
    if (std::find(allowed.begin(), allowed.end(), key) == allowed.end()) {
      std::string list;
      for (const auto& a : allowed) list += (list.empty() ? "" : ", ") + a;
      fail(source, entry.first, name + "." + key, key, "keys: " + list);
    }
    visit(name + "." + key, entry.second);
  }
}

// "ROWSxCOLS" or "N", each a whole number in [1, 4096] (the scenarios' own range).
bool mesh_shape(const std::string& text) {
  const auto side = [](std::string_view digits) {
    if (digits.empty() || digits.size() > 4) return false;
    unsigned value = 0;
    const auto [end, error] = std::from_chars(digits.data(), digits.data() + digits.size(), value);
    return error == std::errc() && end == digits.data() + digits.size() && value >= 1 &&
           value <= 4096;
  };
  const std::string_view view(text);
  const size_t cross = view.find('x');
  if (cross == std::string_view::npos) return side(view);
  return side(view.substr(0, cross)) && side(view.substr(cross + 1));
}

void check_axis_value(const std::string& source, const YAML::Node& node, const std::string& key,
                      const std::string& text) {
  if (key == "integrator.plugin" || key == "scenario.plugin") {
    if (!host::is_plugin_id(text)) fail(source, node, key, text, "a plugin id ([a-z0-9_-]+)");
  } else if (key == "mesh") {
    if (!mesh_shape(text)) fail(source, node, key, text, "ROWSxCOLS or N, each in [1, 4096]");
  }
}

Axis read_axis(const std::string& source, const std::string& name, const YAML::Node& node) {
  Axis axis{config::canonical_key(name), {}};
  const std::string key = "sweep.matrix." + name;
  if (node.IsScalar()) {
    axis.values.push_back({axis.key, node.Scalar(), location(source, node)});
  } else if (node.IsSequence() && node.size() > 0) {
    for (const YAML::Node& item : node) {
      axis.values.push_back({axis.key, scalar_text(source, item, key), location(source, item)});
    }
  } else {
    fail(source, node, key, "(empty)", "a value or a non-empty list of values");
  }
  std::set<std::string> seen;
  for (std::size_t i = 0; i < axis.values.size(); ++i) {
    const YAML::Node item = node.IsSequence() ? node[i] : node;
    check_axis_value(source, item, axis.key, axis.values[i].value);
    if (!seen.insert(host::canonical_value(axis.values[i].value)).second) {
      fail(source, item, key, axis.values[i].value, "each value once");
    }
  }
  return axis;
}

SweepMode read_mode(const std::string& source, const YAML::Node& node) {
  const std::string text = node.IsScalar() ? node.Scalar() : "(not a value)";
  if (text == "run") return SweepMode::Run;
  if (text == "work-precision") return SweepMode::WorkPrecision;
  if (text == "stability") return SweepMode::Stability;
  fail(source, node, "sweep.mode", text, "run, work-precision or stability");
}

void read_monitor(const std::string& source, const YAML::Node& node, SweepSpec& spec) {
  for_each_key(source, node, "sweep.monitor",
               {"check_interval", "stretch_limit", "energy_margin", "wind_work_safety"},
               [&](const std::string& key, const YAML::Node& value) {
                 if (key.ends_with("check_interval")) {
                   spec.monitor.check_interval =
                       static_cast<uint64_t>(whole_number(source, value, key, 1, 1e9));
                 } else if (key.ends_with("stretch_limit")) {
                   spec.monitor.stretch_limit =
                       number(source, value, key, 1.0 + 1e-9, 1e6, "a number in (1, 1e6]");
                 } else if (key.ends_with("energy_margin")) {
                   spec.monitor.energy_margin =
                       number(source, value, key, 0.0, 1e12, "a number in [0, 1e12]");
                 } else {
                   spec.monitor.wind_work_safety =
                       number(source, value, key, 1.0, 1e6, "a number in [1, 1e6]");
                 }
               });
}

void read_work_precision(const std::string& source, const YAML::Node& node, SweepSpec& spec) {
  auto& wp = spec.work_precision;
  for_each_key(source, node, "sweep.work_precision",
               {"reference_integrator", "self_reference", "refinement", "dt_start", "levels"},
               [&](const std::string& key, const YAML::Node& value) {
                 if (key.ends_with("reference_integrator")) {
                   wp.reference_integrator = scalar_text(source, value, key);
                   if (!host::is_plugin_id(wp.reference_integrator)) {
                     fail(source, value, key, wp.reference_integrator, "a plugin id");
                   }
                 } else if (key.ends_with("self_reference")) {
                   const YAML::Node list = value.IsSequence() ? value : YAML::Node();
                   if (!value.IsSequence())
                     fail(source, value, key, "(not a list)", "a list of ids");
                   for (const YAML::Node& item : list) {
                     const std::string id = scalar_text(source, item, key);
                     if (!host::is_plugin_id(id)) fail(source, item, key, id, "a plugin id");
                     wp.self_reference.push_back(id);
                   }
                 } else if (key.ends_with("refinement")) {
                   wp.refinement = number(source, value, key, 2.0, 1e6, "a number in [2, 1e6]");
                 } else if (key.ends_with("dt_start")) {
                   wp.dt_start = number(source, value, key, 1e-9, 10.0, "a number in [1e-9, 10] s");
                 } else {
                   wp.levels = static_cast<int>(whole_number(source, value, key, 2, 30));
                 }
               });
}

void read_stability(const std::string& source, const YAML::Node& node, SweepSpec& spec) {
  auto& st = spec.stability;
  for_each_key(source, node, "sweep.stability",
               {"dt_initial", "dt_min", "dt_max", "tolerance", "growth", "max_evaluations"},
               [&](const std::string& key, const YAML::Node& value) {
                 const std::string seconds = "a number in [1e-12, 100] s";
                 if (key.ends_with("dt_initial")) {
                   st.dt_initial = number(source, value, key, 1e-12, 100.0, seconds);
                 } else if (key.ends_with("dt_min")) {
                   st.dt_lower_limit = number(source, value, key, 1e-12, 100.0, seconds);
                 } else if (key.ends_with("dt_max")) {
                   st.dt_upper_limit = number(source, value, key, 1e-12, 100.0, seconds);
                 } else if (key.ends_with("growth")) {
                   st.growth = number(source, value, key, 1.01, 100.0, "a number in [1.01, 100]");
                 } else if (key.ends_with("tolerance")) {
                   st.relative_tolerance =
                       number(source, value, key, 1e-6, 0.5, "a number in [1e-6, 0.5]");
                 } else {
                   st.max_evaluations = static_cast<int>(whole_number(source, value, key, 1, 1000));
                 }
               });
  if (!(st.dt_lower_limit < st.dt_upper_limit && st.dt_initial >= st.dt_lower_limit &&
        st.dt_initial <= st.dt_upper_limit)) {
    fail(source, node, "sweep.stability",
         "dt_min " + host::format_number(st.dt_lower_limit) + ", dt_initial " +
             host::format_number(st.dt_initial) + ", dt_max " +
             host::format_number(st.dt_upper_limit),
         "dt_min < dt_max and dt_initial between them");
  }
}

void read_slurm(const std::string& source, const YAML::Node& node, SweepSpec& spec) {
  for_each_key(source, node, "slurm", {"partition", "tasks", "time", "cpus_per_task", "sbatch"},
               [&](const std::string& key, const YAML::Node& value) {
                 if (key == "slurm.sbatch" && value.IsSequence()) {
                   for (const YAML::Node& item : value)
                     apply_slurm_setting(spec.slurm, key, scalar_text(source, item, key),
                                         location(source, item));
                 } else {
                   apply_slurm_setting(spec.slurm, key, scalar_text(source, value, key),
                                       location(source, value));
                 }
               });
}

void check_fixed(const std::string& source, const SweepSpec& spec, const YAML::Node& root) {
  bool has_steps = false, has_duration = false;
  for (const Setting& setting : spec.fixed) {
    has_steps |= setting.key == "steps";
    has_duration |= setting.key == "duration";
  }
  if (has_steps && has_duration) {
    fail(source, root, "steps/duration", "both", "one of steps or duration");
  }
  if (!has_steps && !has_duration) {
    fail(source, root, "steps/duration", "(missing)", "one of steps or duration at the top level");
  }
}

void check_mode_axes(const std::string& source, const YAML::Node& matrix, const SweepSpec& spec) {
  bool has_dt_axis = false, has_integrator_axis = false;
  for (const Axis& axis : spec.axes) {
    has_dt_axis |= axis.key == "dt";
    has_integrator_axis |= axis.key == "integrator.plugin";
  }
  const bool has_fixed_dt = std::any_of(spec.fixed.begin(), spec.fixed.end(),
                                        [](const Setting& s) { return s.key == "dt"; });
  if (spec.mode == SweepMode::Run && !has_dt_axis && !has_fixed_dt) {
    fail(source, matrix, "sweep.matrix.dt", "(missing)", "a dt list (or a fixed dt) in run mode");
  }
  if (spec.mode != SweepMode::Run && has_dt_axis) {
    fail(source, matrix, "sweep.matrix.dt", "(a list)",
         std::string("no dt axis in ") + to_string(spec.mode) + " mode (it chooses dt itself)");
  }
  if (!has_integrator_axis) {
    fail(source, matrix, "sweep.matrix.integrator", "(missing)", "a list of integrator ids");
  }
}

}  // namespace

const char* to_string(SweepMode mode) {
  switch (mode) {
    case SweepMode::Run:
      return "run";
    case SweepMode::WorkPrecision:
      return "work-precision";
    case SweepMode::Stability:
      return "stability";
  }
  return "unknown";
}

namespace {

// sbatch --time forms: M, M:S, H:M:S, D-H, D-H:M, D-H:M:S (groups after the first: 1-2 digits).
bool is_slurm_time(const std::string& text) {
  const std::size_t dash = text.find('-');
  if (dash != std::string::npos &&
      (dash == 0 || dash > 4 || text.find_first_not_of("0123456789") < dash))
    return false;
  const std::string clock = dash == std::string::npos ? text : text.substr(dash + 1);
  std::size_t groups = 0, start = 0;
  while (start <= clock.size()) {
    const std::size_t end = std::min(clock.find(':', start), clock.size());
    const std::size_t digits = end - start;
    if (digits == 0 || digits > (groups == 0 ? 6 : 2) ||
        clock.substr(start, digits).find_first_not_of("0123456789") != std::string::npos)
      return false;
    ++groups;
    start = end + 1;
  }
  return groups <= 3;
}

}  // namespace

void apply_slurm_setting(SlurmSettings& slurm, const std::string& key, const std::string& value,
                         const std::string& source) {
  const auto bad = [&](const std::string& allowed) {
    throw SweepError(source + ": " + key + " = '" + value + "': allowed " + allowed);
  };
  const auto count = [&](double high) {
    const auto number = host::parse_real(value);
    const std::string allowed = "a whole number in [1, " + host::format_number(high) + "]";
    if (!number || *number < 1 || *number > high || *number != std::floor(*number)) bad(allowed);
    return static_cast<std::size_t>(*number);
  };
  if (key == "slurm.partition") {
    const bool plain = !value.empty() && value.size() <= 64 &&
                       value.find_first_not_of(
                           "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz"
                           "0123456789_.-") == std::string::npos;
    if (!plain) bad("a partition name: up to 64 of [A-Za-z0-9_.-]");
    slurm.partition = value;
  } else if (key == "slurm.tasks") {
    slurm.tasks = count(100000);
  } else if (key == "slurm.cpus_per_task") {
    slurm.cpus_per_task = count(1024);
  } else if (key == "slurm.time") {
    if (!is_slurm_time(value)) bad("a Slurm time: MM, MM:SS, H:MM:SS or D-HH[:MM[:SS]]");
    slurm.time = value;
  } else if (key == "slurm.sbatch") {
    if (!value.starts_with("--") || value.find_first_of(" \t\n") != std::string::npos)
      bad("sbatch options of the form --name or --name=value, one per list item");
    slurm.sbatch_options.push_back(value);
  } else {
    bad("keys slurm.partition, slurm.tasks, slurm.time, slurm.cpus_per_task, slurm.sbatch");
  }
}

SweepSpec parse_sweep(const std::string& yaml_text, const std::string& source) {
  return parse_sweep(config::load_yaml_text(yaml_text, source), source);
}

SweepSpec parse_sweep(const YAML::Node& root, const std::string& source) {
  if (!root.IsMap()) fail(source, root, "(document)", "(not a map)", "a map of settings");
  const YAML::Node section = root["sweep"];
  if (!section) fail(source, root, "sweep", "(missing)", "a sweep: section");
  SweepSpec spec;
  spec.source = source;
  // The one flattener checks the whole file (repeated keys, empty maps, bounds); the keys
  // outside `sweep:` and `slurm:` are the fixed settings of every case.
  for (Setting& setting : config::flatten_settings(root, source))
    if (!setting.key.starts_with("sweep.") && !setting.key.starts_with("slurm."))
      spec.fixed.push_back(std::move(setting));
  bool has_matrix = false;
  for_each_key(source, section, "sweep",
               {"name", "mode", "output", "matrix", "monitor", "work_precision", "stability"},
               [&](const std::string& key, const YAML::Node& value) {
                 if (key == "sweep.name") {
                   spec.name = scalar_text(source, value, key);
                   if (!host::is_plugin_id(spec.name))
                     fail(source, value, key, spec.name, "[a-z0-9_-]+");
                 } else if (key == "sweep.mode") {
                   spec.mode = read_mode(source, value);
                 } else if (key == "sweep.output") {
                   spec.output = scalar_text(source, value, key);
                   if (spec.output.empty())
                     fail(source, value, key, "", "a path without extension");
                 } else if (key == "sweep.matrix") {
                   has_matrix = true;
                   if (!value.IsMap())
                     fail(source, value, key, "(not a map)", "a map of key: [values]");
                   for (const auto& entry : value) {
                     spec.axes.push_back(
                         read_axis(source, config::key_text(entry.first, source), entry.second));
                   }
                 } else if (key == "sweep.monitor") {
                   read_monitor(source, value, spec);
                 } else if (key == "sweep.work_precision") {
                   read_work_precision(source, value, spec);
                 } else {
                   read_stability(source, value, spec);
                 }
               });
  if (spec.name.empty()) fail(source, section, "sweep.name", "(missing)", "[a-z0-9_-]+");
  if (!has_matrix) fail(source, section, "sweep.matrix", "(missing)", "a map of key: [values]");
  if (spec.output.empty()) spec.output = std::filesystem::path("results") / spec.name;
  if (root["slurm"]) read_slurm(source, root["slurm"], spec);
  check_mode_axes(source, section["matrix"], spec);
  check_fixed(source, spec, root);
  return spec;
}

SweepSpec load_sweep(const std::filesystem::path& path) {
  return parse_sweep(config::load_yaml_file(path), path.string());
}

bool is_sweep_file(const std::filesystem::path& path) {
  try {
    const YAML::Node root = config::load_yaml_file(path);
    return root.IsMap() && root["sweep"];
  } catch (const host::InputError&) {
    return false;  // reading it as a single-run config reports the problem
  }
}

}  // namespace clothlab::sweep
