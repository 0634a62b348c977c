// The key table is the one source of --help, the unknown-key message, validation and defaults:
// every test loops over the table, so a key added to it is covered without a new test.
#include "run_keys.hpp"

#include <gtest/gtest.h>

#include <cctype>
#include <clothlab/host/errors.hpp>
#include <clothlab/host/param_text.hpp>

#include "command_line.hpp"
#include "run_config.hpp"

namespace clothlab::cli {
namespace {

// Help text wraps lines anywhere (Boost even inside words): compare without white space.
std::string without_spaces(const std::string& text) {
  std::string result;
  for (const char c : text)
    if (!std::isspace(static_cast<unsigned char>(c))) result += c;
  return result;
}

std::string resolve_error(const std::vector<Setting>& settings) {
  try {
    resolve_run_config(settings);
  } catch (const host::InputError& error) {
    return error.what();
  }
  return "";
}

bool is_number(KeyType type) {
  return type == KeyType::Real || type == KeyType::PositiveReal || type == KeyType::Whole;
}

// A plain key's name, or a family's with a made-up parameter ("integrator.damping").
std::string example_key(const KeyInfo& info) {
  std::string key = info.key;
  const size_t open = key.find('<');
  if (open == std::string::npos) return key;
  key = key.substr(0, open);
  return key == "plugin_params." ? key + "verlet.damping" : key + "damping";
}

TEST(RunKeys, EveryKeyIsInTheHelpWithWhatItAllowsAndItsDefault) {
  const std::string help = without_spaces(usage_text());
  ASSERT_GT(run_keys().size(), 30u);
  for (const KeyInfo& info : run_keys()) {
    std::string line = std::string(info.key) + info.help + "; allowed: " + describe_allowed(info);
    if (info.default_value) line += std::string("; default ") + info.default_value;
    EXPECT_NE(help.find(without_spaces(line)), std::string::npos) << info.key << "\n" << line;
    if (info.flag) {
      std::string flag_line = std::string("--") + info.flag + " arg " + info.help + " (key " +
                              info.key + ": " + describe_allowed(info);
      if (info.default_value) flag_line += std::string(", default ") + info.default_value;
      EXPECT_NE(help.find(without_spaces(flag_line + ")")), std::string::npos) << flag_line;
    }
  }
}

TEST(RunKeys, EveryFlagSetsItsKey) {
  for (const KeyInfo& info : run_keys()) {
    if (!info.flag) continue;
    const std::string flag = std::string("--") + info.flag;
    const char* argv[] = {"clothlab", flag.c_str(), "7"};
    const CommandLine command_line = parse_command_line(3, argv);
    ASSERT_EQ(command_line.settings.size(), 1u) << flag;
    EXPECT_EQ(command_line.settings[0].key, info.key);
    EXPECT_EQ(command_line.settings[0].source, flag);
  }
}

// A run config refuses, with the table's allowed text, a value just outside each number key's
// range: the table's range is the one resolve_run_config applies, for every key.
TEST(RunKeys, EveryNumberKeyIsCheckedAgainstTheTablesRange) {
  for (const KeyInfo& info : run_keys()) {
    if (!is_number(info.type)) continue;
    const std::string allowed = "; allowed: " + describe_allowed(info);
    const double above = info.max_value == 0 ? 1 : info.max_value * 2;
    const double below = info.type == KeyType::PositiveReal ? 0.0 : info.min_value - 1;
    for (const double outside : {above, below}) {
      const std::string text = host::format_number(outside);
      EXPECT_EQ(resolve_error({{info.key, text, "SRC"}}),
                std::string("SRC: ") + info.key + " = " + text + ": out of range" + allowed)
          << info.key;
    }
    EXPECT_EQ(check_value(info, {info.key, host::format_number(info.max_value), "SRC"}).number,
              info.max_value)
        << info.key;
    if (info.type != KeyType::PositiveReal) {
      EXPECT_EQ(check_value(info, {info.key, host::format_number(info.min_value), "SRC"}).number,
                info.min_value)
          << info.key;
    }
    if (info.type == KeyType::Whole) {
      EXPECT_EQ(resolve_error({{info.key, "1.5", "SRC"}}),
                std::string("SRC: ") + info.key + " = 1.5: not a whole number" + allowed);
    }
  }
}

TEST(RunKeys, EveryOtherKeyIsCheckedByItsType) {
  for (const KeyInfo& info : run_keys()) {
    const std::string allowed = "; allowed: " + describe_allowed(info);
    const std::string key = example_key(info);
    switch (info.type) {
      case KeyType::Choice:
      case KeyType::ChoiceList:
        EXPECT_NE(resolve_error({{key, "nonsense", "SRC"}})
                      .find("SRC: " + key + " = nonsense: unknown value"),
                  std::string::npos)
            << key;
        EXPECT_NE(resolve_error({{key, "nonsense", "SRC"}}).find(allowed), std::string::npos);
        break;
      case KeyType::NonEmptyText:
        EXPECT_EQ(resolve_error({{key, "", "SRC"}}), "SRC: " + key + " is empty" + allowed);
        break;
      case KeyType::Names:
        EXPECT_EQ(resolve_error({{key, "[a, ]", "SRC"}}),
                  "SRC: " + key + " = [a, ]: an empty name" + allowed);
        break;
      case KeyType::Mesh:
        EXPECT_EQ(resolve_error({{key, "3x" + host::format_number(info.max_value + 1), "SRC"}}),
                  "SRC: " + key + " = 3x" + host::format_number(info.max_value + 1) +
                      ": not a mesh" + allowed);
        EXPECT_EQ(check_value(info, {key, "7", "SRC"}).text, "7x7");
        break;
      case KeyType::PluginParameter:
        // Checked by the plugin once it is loaded; the run config only collects it.
        EXPECT_EQ(find_run_key(key), &info) << key;
        EXPECT_EQ(resolve_error({{key, "anything", "SRC"}}), "");
        break;
      case KeyType::Text:
      case KeyType::Real:
      case KeyType::PositiveReal:
      case KeyType::Whole:
        break;
    }
  }
}

TEST(RunKeys, EveryDefaultIsAllowedByItsOwnKey) {
  for (const KeyInfo& info : run_keys()) {
    if (info.default_value) {
      EXPECT_NO_THROW(check_value(info, {info.key, info.default_value, "default"})) << info.key;
    }
  }
  const RunConfig defaults = resolve_run_config({});
  EXPECT_EQ(defaults.dt, 0.001);
  EXPECT_EQ(defaults.steps, 2000u);  // duration 2 s at dt 1 ms
  EXPECT_EQ(defaults.integrator, "rk4");
  EXPECT_EQ(defaults.integrator_source, "default integrator.plugin");
}

// The choose.* defaults in the table (the ones --help shows and the CLI applies) are the search
// library's own, so a program calling sweep::choose_integrators searches as `--choose` does.
TEST(RunKeys, ChooseDefaultsAreTheSearchLibrarysDefaults) {
  const sweep::ChoiceSettings library;
  const sweep::ChoiceSettings table = resolve_configuration({}).choose.search;
  EXPECT_EQ(table.duration, library.duration);
  EXPECT_EQ(table.error_duration, library.error_duration);
  EXPECT_EQ(table.stretch_limit, library.stretch_limit);
  EXPECT_EQ(table.error_tolerance, library.error_tolerance);
  EXPECT_EQ(table.max_substeps, library.max_substeps);
  EXPECT_EQ(table.max_iterations, library.max_iterations);
  EXPECT_EQ(table.probe_timeout_s, library.probe_timeout_s);
  EXPECT_EQ(table.stop_factor, library.stop_factor);
  EXPECT_EQ(table.reference_substeps, library.reference_substeps);
  EXPECT_EQ(table.reference_integrator, library.reference_integrator);
  EXPECT_EQ(table.error_mesh, library.error_mesh);
}

// The same for the monitor, the dt search and a sweep's sections: a program that builds these
// structs itself judges, searches and sweeps as the command line does.
TEST(RunKeys, MonitorSearchAndSweepDefaultsAreTheLibrariesDefaults) {
  const Configuration table = resolve_configuration({});
  const analysis::MonitorOptions monitor;
  EXPECT_EQ(table.run.monitor.check_interval, monitor.check_interval);
  EXPECT_EQ(table.run.monitor.stretch_limit, monitor.stretch_limit);
  EXPECT_EQ(table.run.monitor.energy_margin, monitor.energy_margin);
  EXPECT_EQ(table.run.monitor.wind_work_safety, monitor.wind_work_safety);
  const analysis::MaxDtOptions search;
  EXPECT_EQ(table.find_max_dt.dt_lower_limit, search.dt_lower_limit);
  EXPECT_EQ(table.find_max_dt.dt_upper_limit, search.dt_upper_limit);
  EXPECT_EQ(table.find_max_dt.relative_tolerance, search.relative_tolerance);
  EXPECT_EQ(table.find_max_dt.growth, search.growth);
  EXPECT_EQ(table.find_max_dt.max_evaluations, search.max_evaluations);
  const sweep::WorkPrecisionSettings ladder;
  EXPECT_EQ(table.sweep.work_precision.reference_integrator, ladder.reference_integrator);
  EXPECT_EQ(table.sweep.work_precision.refinement, ladder.refinement);
  EXPECT_EQ(table.sweep.work_precision.dt_start, ladder.dt_start);
  EXPECT_EQ(table.sweep.work_precision.levels, ladder.levels);
  const sweep::SlurmSettings slurm;
  EXPECT_EQ(table.sweep.slurm.tasks, slurm.tasks);
  EXPECT_EQ(table.sweep.slurm.cpus_per_task, slurm.cpus_per_task);
}

TEST(RunKeys, UnknownKeyListsTheTableAndSuggestsTheNearest) {
  std::string valid;
  for (const KeyInfo& info : run_keys())
    valid += (valid.empty() ? "" : ", ") + std::string(info.key);
  EXPECT_EQ(resolve_error({{"stepz", "10", "f.yaml:2:1"}}),
            "f.yaml:2:1: unknown key stepz (did you mean steps?); valid: " + valid);
  EXPECT_EQ(resolve_error({{"frames.formt", "vtp", "--set"}}),
            "--set: unknown key frames.formt (did you mean frames.format?); valid: " + valid);
  EXPECT_EQ(resolve_error({{"colour", "red", "--set"}}),
            "--set: unknown key colour; valid: " + valid);
  // A family needs its parameter: "integrator." alone and plugin_params.<id> without one are
  // no keys.
  EXPECT_EQ(find_run_key("integrator."), nullptr);
  EXPECT_EQ(find_run_key("plugin_params.verlet"), nullptr);
}

}  // namespace
}  // namespace clothlab::cli
