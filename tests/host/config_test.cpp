#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <clothlab/host/errors.hpp>
#include <fstream>

#include "command_line.hpp"
#include "config_file.hpp"
#include "run_config.hpp"

namespace clothlab::cli {
namespace {

namespace fs = std::filesystem;

// Writes text to a fresh YAML file, removed with the object.
class TempConfig {
 public:
  explicit TempConfig(const std::string& text)
      : path_(fs::temp_directory_path() / ("clothlab_config_" + std::to_string(getpid()) + "_" +
                                           std::to_string(next_++) + ".yaml")) {
    std::ofstream(path_) << text;
  }
  ~TempConfig() { fs::remove(path_); }
  const fs::path& path() const { return path_; }
  std::string at(int line, int column) const {
    return path_.string() + ":" + std::to_string(line) + ":" + std::to_string(column);
  }

 private:
  static inline int next_ = 0;
  fs::path path_;
};

std::string config_error(const TempConfig& config) {
  try {
    resolve_run_config(read_config_file(config.path()));
  } catch (const host::InputError& error) {
    return error.what();
  }
  return "";
}

TEST(ConfigFile, NestedMapsFlattenToDottedKeysWithTheirPositions) {
  const TempConfig config(
      "integrator: rk4\n"
      "scenario:\n"
      "  plugin: flag\n"
      "  structural: {ks: 50, kd: 2}\n"
      "  gravity: [0, -9.81, 0]\n"
      "dt: 0.002\n");
  const std::vector<Setting> settings = read_config_file(config.path());
  ASSERT_EQ(settings.size(), 6u);
  EXPECT_EQ(settings[0].key, "integrator.plugin");
  EXPECT_EQ(settings[0].value, "rk4");
  EXPECT_EQ(settings[0].source, config.at(1, 13));
  EXPECT_EQ(settings[1].key, "scenario.plugin");
  EXPECT_EQ(settings[2].key, "scenario.structural.ks");
  EXPECT_EQ(settings[2].value, "50");
  EXPECT_EQ(settings[2].source, config.at(4, 20));
  EXPECT_EQ(settings[3].key, "scenario.structural.kd");
  EXPECT_EQ(settings[4].key, "scenario.gravity");
  EXPECT_EQ(settings[4].value, "[0, -9.81, 0]");
  EXPECT_EQ(settings[5].key, "dt");
}

TEST(ConfigFile, ResolvesIntoARunConfig) {
  const TempConfig config(
      "integrator: {plugin: verlet, damping: 0.5}\n"
      "scenario: sheet\n"
      "dt: 0.002\n"
      "duration: 1.5\n"
      "precision: float64\n"
      "threads: 2\n"
      "scenario.rows: 30\n");
  const RunConfig run = resolve_run_config(read_config_file(config.path()));
  EXPECT_EQ(run.integrator, "verlet");
  EXPECT_EQ(run.scenario, "sheet");
  EXPECT_EQ(run.dt, 0.002);
  EXPECT_EQ(run.steps, 750u);  // 1.5 s / 2 ms
  EXPECT_TRUE(run.float64);
  EXPECT_EQ(run.threads, 2);
  ASSERT_EQ(run.integrator_params.size(), 1u);
  EXPECT_EQ(run.integrator_params[0].key, "damping");
  ASSERT_EQ(run.scenario_params.size(), 1u);
  EXPECT_EQ(run.scenario_params[0].key, "rows");
  EXPECT_EQ(run.scenario_params[0].value, "30");
}

TEST(ConfigFile, UnknownKeyNamesFileLineAndColumn) {
  const TempConfig config("dt: 0.001\nstepz: 10\n");
  const std::string message = config_error(config);
  EXPECT_EQ(message.rfind(config.at(2, 8) + ": unknown key stepz (did you mean steps?); valid:", 0),
            0u)
      << message;
}

TEST(ConfigFile, WrongTypeNamesPositionKeyValueAndAllowed) {
  const TempConfig config("integrator: rk4\ndt: fast\n");
  EXPECT_EQ(config_error(config),
            config.at(2, 5) + ": dt = fast: not a finite number; allowed: real in (0, 10] s");
}

TEST(ConfigFile, OutOfRangeValueIsAnError) {
  const TempConfig config("steps: 0\n");
  EXPECT_EQ(config_error(config),
            config.at(1, 8) + ": steps = 0: out of range; allowed: int in [1, 1e+09]");
}

TEST(ConfigFile, UnknownPrecisionIsAnError) {
  const TempConfig config("precision: float16\n");
  EXPECT_EQ(config_error(config), config.at(1, 12) +
                                      ": precision = float16: unknown value; allowed: "
                                      "float32 or float64");
}

TEST(ConfigFile, SyntaxErrorNamesItsPosition) {
  const TempConfig config("dt: 0.001\nscenario: [sheet\n");
  const std::string message = config_error(config);
  EXPECT_EQ(message.rfind(config.path().string() + ":", 0), 0u) << message;
  EXPECT_NE(message.find("YAML syntax error"), std::string::npos) << message;
}

TEST(ConfigFile, EmptyValueIsAnError) {
  const TempConfig config("dt:\n");
  EXPECT_NE(config_error(config).find(config.at(1, 1) + ": dt has no value"), std::string::npos);
}

TEST(ConfigFile, StepsAndDurationTogetherAreAnError) {
  const TempConfig config("steps: 10\nduration: 1\n");
  EXPECT_NE(config_error(config).find("steps or duration, not both"), std::string::npos);
}

TEST(ConfigFile, TheSameKeyTwiceIsAnError) {
  const TempConfig config("scenario:\n  rows: 5\nscenario.rows: 6\n");
  EXPECT_EQ(config_error(config), config.at(3, 16) +
                                      ": scenario.rows = 6 repeats the key already set at " +
                                      config.at(2, 9) + "; allowed: each key once per file");
}

TEST(ConfigFile, PluginParamsAreKeptPerPluginId) {
  const TempConfig config("plugin_params:\n  verlet: {damping_per_step: 0.005}\n");
  const RunConfig run = resolve_run_config(read_config_file(config.path()));
  ASSERT_EQ(run.plugin_params.size(), 1u);
  EXPECT_EQ(run.plugin_params[0].key, "verlet.damping_per_step");
  EXPECT_EQ(run.plugin_params[0].value, "0.005");
  EXPECT_TRUE(run.integrator_params.empty());
}

TEST(ConfigFile, MissingFileIsAnError) {
  EXPECT_THROW(read_config_file("/nonexistent/clothlab.yaml"), host::InputError);
}

std::string read_error(const fs::path& path) {
  try {
    read_config_file(path);
  } catch (const host::InputError& error) {
    return error.what();
  }
  return "";
}

// Items 4 and 7 of issue 12: --config /dev/zero read until out of memory, a FIFO blocked, a
// folder gave "basic_filebuf::underflow" without the path.
TEST(ConfigFile, OnlyARegularFileOfBoundedSizeIsRead) {
  EXPECT_EQ(read_error("/dev/zero"),
            "/dev/zero: is not a regular file (a FIFO or device); allowed: a YAML file");
  const fs::path folder = fs::temp_directory_path() / ("clothlab_fifo_" + std::to_string(getpid()));
  fs::create_directories(folder);
  ASSERT_EQ(::mkfifo((folder / "fifo.yaml").c_str(), 0600), 0);
  EXPECT_EQ(read_error(folder / "fifo.yaml"),
            (folder / "fifo.yaml").string() +
                ": is not a regular file (a FIFO or device); allowed: a YAML file");
  EXPECT_EQ(read_error(folder), folder.string() + ": is a folder; allowed: a YAML file");
  std::ofstream(folder / "big.yaml") << "# " << std::string(2 << 20, 'x') << "\n";
  EXPECT_EQ(read_error(folder / "big.yaml"),
            (folder / "big.yaml").string() + ": 2097155 bytes; allowed: at most 1 MiB");
  fs::remove_all(folder);
}

TEST(ConfigFile, EmptyMapsSecondDocumentsAndComplexKeysAreErrors) {
  const TempConfig empty_map("dt: {}\n");
  EXPECT_EQ(
      config_error(empty_map),
      empty_map.at(1, 5) +
          ": dt = {}: an empty map sets nothing; allowed: a value, a list or a map of settings");
  const TempConfig second("dt: 0.001\n---\ndt: 0.002\n");
  EXPECT_NE(config_error(second).find("a second YAML document"), std::string::npos);
  const TempConfig complex_key("? [a, b]\n: 1\n");
  EXPECT_EQ(config_error(complex_key),
            complex_key.at(1, 3) + ": keys must be plain names; allowed: name: value");
}

CommandLine parse(std::vector<const char*> arguments) {
  arguments.insert(arguments.begin(), "clothlab");
  return parse_command_line(static_cast<int>(arguments.size()), arguments.data());
}

TEST(CommandLine, FlagsAndSetBecomeSettings) {
  const CommandLine command_line = parse(
      {"--integrator=rk4.so", "--dt", "0.01", "--set", "scenario.rows=5", "--json", "o.json"});
  ASSERT_EQ(command_line.settings.size(), 3u);
  EXPECT_EQ(command_line.settings[0].key, "integrator.plugin");
  EXPECT_EQ(command_line.settings[0].value, "rk4.so");
  EXPECT_EQ(command_line.settings[0].source, "--integrator");
  EXPECT_EQ(command_line.settings[1].key, "dt");
  EXPECT_EQ(command_line.settings[2].key, "scenario.rows");
  EXPECT_EQ(command_line.settings[2].value, "5");
  EXPECT_EQ(command_line.settings[2].source, "--set");
  EXPECT_EQ(command_line.json_file, "o.json");
}

TEST(CommandLine, BadArgumentsAreInputErrors) {
  EXPECT_THROW(parse({"--set", "scenario.rows"}), host::InputError);
  EXPECT_THROW(parse({"--no-such-option"}), host::InputError);
  EXPECT_THROW(parse({"--dt"}), host::InputError);
  EXPECT_THROW(parse({"stray-word"}), host::InputError);
  EXPECT_THROW(parse({"--steps", "5", "--duration", "1"}), host::InputError);
}

TEST(RunConfig, CommandLineOverridesTheConfigFile) {
  const TempConfig config("integrator: euler\nduration: 1\nscenario: {rows: 10}\n");
  std::vector<Setting> settings = read_config_file(config.path());
  const CommandLine command_line =
      parse({"--integrator", "rk4", "--steps", "7", "--set", "scenario.rows=12"});
  settings.insert(settings.end(), command_line.settings.begin(), command_line.settings.end());
  const RunConfig run = resolve_run_config(settings);
  EXPECT_EQ(run.integrator, "rk4");
  EXPECT_EQ(run.steps, 7u);  // --steps replaces the file's duration
  ASSERT_EQ(run.scenario_params.size(), 2u);
  EXPECT_EQ(run.scenario_params.back().value, "12");  // applied last, so it wins
}

TEST(RunConfig, DefaultsAreTwoSecondsOfOneMillisecondSteps) {
  const RunConfig run = resolve_run_config({});
  EXPECT_EQ(run.dt, 0.001);
  EXPECT_EQ(run.steps, 2000u);
  EXPECT_FALSE(run.float64);
}

TEST(RunConfig, DurationShorterThanAStepIsAnError) {
  EXPECT_THROW(resolve_run_config({{"dt", "0.1", "--dt"}, {"duration", "0.01", "--duration"}}),
               host::InputError);
}

}  // namespace
}  // namespace clothlab::cli
