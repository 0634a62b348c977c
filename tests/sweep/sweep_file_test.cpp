#include "sweep_file.hpp"

#include <gtest/gtest.h>

#include <clothlab/host/errors.hpp>

#include "clothlab/sweep/case_spec.hpp"
#include "clothlab/sweep/sweep_error.hpp"
#include "run_config.hpp"
#include "sweep_test_support.hpp"

namespace clothlab::sweep {
namespace {

using cli::is_sweep_file;
using cli::load_sweep;
using cli::parse_sweep;

const char* kValid = R"(scenario:
  mass: 100
  structural: {ks: 20, kd: 7.5}
duration: 2
stability: {interval: 4, max_stretch: 3, wind_work_safety: 3}
sweep:
  name: tiny
  mode: run
  output: out/tiny
  matrix:
    integrator: [euler, rk4]
    scenario: sheet
    mesh: [4x6, 8]
    dt: [1e-3, 0.005]
    scenario.flexion.ks: [5, 50]
)";

TEST(SweepFile, ReadsMatrixFixedSettingsAndSections) {
  const SweepSpec spec = parse_sweep(kValid, "tiny.yaml");
  EXPECT_EQ(spec.name, "tiny");
  EXPECT_EQ(spec.mode, SweepMode::Run);
  EXPECT_EQ(spec.output, std::filesystem::path("out/tiny"));
  ASSERT_EQ(spec.axes.size(), 5u);
  EXPECT_EQ(spec.axes[0].key, "integrator.plugin");
  EXPECT_EQ(spec.axes[1].key, "scenario.plugin");
  EXPECT_EQ(spec.axes[1].values.size(), 1u);
  EXPECT_EQ(spec.axes[4].key, "scenario.flexion.ks");
  EXPECT_EQ(spec.axes[3].values[0].source, "tiny.yaml:14:10");
  ASSERT_EQ(spec.fixed.size(), 7u);
  EXPECT_EQ(spec.fixed[1].key, "scenario.structural.ks");
  EXPECT_EQ(spec.fixed[1].value, "20");
  EXPECT_EQ(spec.fixed[3].key, "duration");
  EXPECT_EQ(spec.fixed[4].key, "stability.interval");
}

// A sweep's monitor settings reach every case's run (sweep.monitor.wind_work_safety was parsed,
// fingerprinted and never applied): they are the run's own keys, read by the one table.
TEST(SweepFile, MonitorSettingsReachEveryCase) {
  for (const CaseSpec& c : expand_cases(parse_sweep(kValid, "tiny.yaml"))) {
    const analysis::MonitorOptions monitor = cli::resolve_run_config(c.settings).monitor;
    EXPECT_EQ(monitor.check_interval, 4u);
    EXPECT_DOUBLE_EQ(monitor.stretch_limit, 3.0);
    EXPECT_DOUBLE_EQ(monitor.wind_work_safety, 3.0);
  }
}

void expect_error(const std::string& yaml, const std::string& fragment) {
  try {
    parse_sweep(yaml, "bad.yaml");
    ADD_FAILURE() << "no error for:\n" << yaml;
  } catch (const host::InputError& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find(fragment), std::string::npos) << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << "one line: " << message;
    EXPECT_EQ(message.rfind("bad.yaml", 0), 0u) << message;
  }
}

TEST(SweepFile, BadInputNamesSourceKeyValueAndAllowedRange) {
  const std::string head = "duration: 1\nsweep:\n  name: x\n";
  expect_error(head + "  mode: fast\n  matrix: {integrator: [rk4], dt: [0.001]}\n",
               "sweep.mode = fast: unknown value; allowed: run, work-precision or stability");
  expect_error(head + "  matrix: {integrator: [rk4], dt: [0.001], mesh: [0x5]}\n",
               "bad.yaml:4:51: mesh = 0x5: not a mesh");
  expect_error(head + "  matrix: {integrator: [rk4], dt: [0.001, 1e-3]}\n", "each value once");
  expect_error(head + "  matrix: {integrator: [rk4], dt: [0.001]}\n  colour: red\n",
               "unknown key sweep.colour");
  expect_error(head + "  matrix: {integrator: [rk4], dt: []}\n", "non-empty list");
  expect_error(head + "  matrix: {integrator: [rk4]}\n", "sweep.matrix.dt");
  expect_error(head + "  mode: stability\n  matrix: {integrator: [rk4], dt: [0.001]}\n",
               "no dt axis in stability mode");
  expect_error(
      "stability: {max_stretch: 0.5}\n" + head + "  matrix: {integrator: [rk4], dt: [0.001]}\n",
      "stability.max_stretch = 0.5: out of range");
  // The settings that had a second name in a sweep are refused there, pointing at the one name.
  expect_error(head + "  matrix: {integrator: [rk4], dt: [0.001]}\n  monitor: {stretch_limit: 2}\n",
               "unknown key sweep.monitor.stretch_limit");
  expect_error("sweep:\n  name: x\n  matrix: {integrator: [rk4], dt: [0.001]}\n",
               "one of steps or duration");
  expect_error("duration: 1\nsweep: {name: x, matrix: {integrator: [rk4], dt: [0.001]}", "YAML");
}

TEST(SweepFile, SlurmSectionIsReadAndIsNoCaseSetting) {
  const std::string sweep =
      "duration: 1\nsweep:\n  name: x\n  matrix: {integrator: [rk4], dt: "
      "[0.001]}\n";
  const SweepSpec spec = parse_sweep(sweep +
                                         "slurm: {tasks: 8, partition: short.q, time: "
                                         "\"1-02:30\", cpus_per_task: 2, sbatch: "
                                         "[--mem=4G, --qos=low]}\n",
                                     "slurm.yaml");
  EXPECT_EQ(spec.slurm.tasks, 8u);
  EXPECT_EQ(spec.slurm.partition, "short.q");
  EXPECT_EQ(spec.slurm.time, "1-02:30");
  EXPECT_EQ(spec.slurm.cpus_per_task, 2u);
  EXPECT_EQ(spec.slurm.sbatch_options, (std::vector<std::string>{"--mem=4G", "--qos=low"}));
  for (const Setting& setting : spec.fixed) EXPECT_FALSE(setting.key.starts_with("slurm"));
  EXPECT_EQ(parse_sweep(sweep, "plain.yaml").slurm.tasks, 4u);  // the default

  expect_error(sweep + "slurm: {tasks: 0}\n", "slurm.tasks = 0: out of range; allowed:");
  expect_error(sweep + "slurm: {time: 1:2:3:4}\n",
               "slurm.time = 1:2:3:4: not allowed; allowed: a Slurm time");
  expect_error(sweep + "slurm: {time: 90x}\n", "slurm.time = 90x");
  expect_error(sweep + "slurm: {partition: \"a b\"}\n", "slurm.partition = a b");
  expect_error(sweep + "slurm: {sbatch: [-N 2]}\n", "slurm.sbatch = [-N 2]: not allowed");
  expect_error(sweep + "slurm: {nodes: 2}\n", "unknown key slurm.nodes");
  for (const char* time : {"30", "5:00", "1:00:00", "2-0", "2-12:00", "2-12:00:00"})
    EXPECT_EQ(parse_sweep(sweep + "slurm: {time: \"" + time + "\"}\n", "t.yaml").slurm.time, time);
}

// The command line's settings come after the file's: a length given there replaces the file's,
// as in a single run; a key the matrix sets is refused, since the matrix would win unseen.
TEST(SweepFile, CommandLineSettingsWinAndMayNotHideAMatrixAxis) {
  const std::string sweep =
      "duration: 1\nsweep:\n  name: x\n  matrix: {integrator: [rk4, euler], dt: [0.001]}\n";
  const SweepSpec spec = parse_sweep(sweep, "cli.yaml", {{"steps", "7", "--steps"}});
  for (const CaseSpec& c : expand_cases(spec))
    EXPECT_EQ(cli::resolve_run_config(c.settings).steps, 7u);
  try {
    parse_sweep(sweep, "cli.yaml", {{"integrator.plugin", "verlet", "--integrator"}});
    ADD_FAILURE() << "an override of a matrix axis was accepted";
  } catch (const host::InputError& error) {
    EXPECT_NE(
        std::string(error.what()).find("--integrator: integrator.plugin = verlet: the matrix"),
        std::string::npos)
        << error.what();
  }
}

// Keys that go together are checked together, whether fixed or on an axis.
TEST(SweepFile, FixedSettingsAreCheckedWithTheMatrixsFirstCase) {
  const SweepSpec spec = parse_sweep(
      "duration: 1\nsubsteps: 4\nsweep:\n  name: x\n  matrix: {integrator: [rk4], frame_rate: "
      "[30, 60]}\n",
      "together.yaml");
  EXPECT_EQ(spec.axes.size(), 2u);
  expect_error(
      "duration: 1\nframe_rate: 60\nsweep:\n  name: x\n  mode: stability\n  matrix: "
      "{integrator: [rk4]}\n",
      "frame_rate = '(set)': allowed no frame_rate in stability mode");
}

// Item 3 of issue 12: a 30 000-character plugin id, sweep name or mesh overflowed the stack
// (std::regex recursed once per character). Now each is an ordinary value or a one-line error.
TEST(SweepFile, VeryLongValuesAreCheckedWithoutRecursion) {
  const std::string letters(30000, 'a');
  const std::string digits(30000, '1');
  const std::string tail = "  matrix: {integrator: [rk4], dt: [0.001]}\n";
  expect_error("duration: 1\nsweep:\n  name: " + letters + "\n" + tail,
               "is 30000 bytes long; allowed: names of at most 255 bytes");
  expect_error("duration: 1\nsweep:\n  name: " + letters + "B\n" + tail, "allowed: [a-z0-9_-]+");
  expect_error(
      "duration: 1\nsweep:\n  name: x\n  matrix: {integrator: [rk4], dt: [0.001], mesh: [" +
          digits + "]}\n",
      "ROWSxCOLS or N, each a whole number in [1, 4096]");
  expect_error(
      "duration: 1\nsweep:\n  name: x\n  matrix: {integrator: [rk4], dt: [0.001], mesh: [5000]}\n",
      "each a whole number in [1, 4096]");
}

// Item 6 of issue 12: a sweep file was read last-wins and with parts ignored, where a run
// config is strict. Now both go through the one flattener (clothlab/config).
TEST(SweepFile, ASweepFileIsAsStrictAsARunConfig) {
  const std::string matrix = "  matrix: {integrator: [rk4], dt: [0.001]}\n";
  expect_error("duration: 1\nsweep:\n  name: x\n  mode: run\n  mode: stability\n" + matrix,
               "sweep.mode = stability repeats the key already set at bad.yaml:4:9");
  expect_error(
      "duration: 1\nsweep:\n  name: x\n  matrix:\n    integrator: [rk4]\n"
      "    dt: [0.001]\n    dt: [0.002]\n",
      "sweep.matrix.dt = [0.002] repeats the key");
  expect_error("duration: 1\ndt: {}\nsweep:\n  name: x\n" + matrix, "bad.yaml:2:5: dt = {}");
  expect_error("duration: 1\nscenario: {}\nsweep:\n  name: x\n" + matrix, "scenario = {}");
  expect_error("duration: 1\nsweep:\n  name: x\n" + matrix + "---\nsteps: 5\n",
               "a second YAML document");
  expect_error("duration: 1\n[a, b]: 1\nsweep:\n  name: x\n" + matrix,
               "bad.yaml:2:1: keys must be plain names");
  expect_error(
      "duration: 1\nsweep:\n  name: x\n  matrix:\n    integrator: [rk4]\n"
      "    dt: [0.001]\n    ? [a]\n    : 1\n",
      "keys must be plain names");
}

// Item 4: a 702-byte alias bomb took 2.3 GB; now it stops at 100000 values.
TEST(SweepFile, AnAliasBombIsRefusedQuickly) {
  std::string yaml = "a0: &a0 [x, x, x, x, x, x, x, x, x, x]\n";
  for (int level = 1; level < 9; ++level) {
    const std::string previous = std::string("*a").append(std::to_string(level - 1));
    const std::string name = std::string("a").append(std::to_string(level));
    yaml += name;
    yaml += ": &";
    yaml += name;
    yaml += " {";
    for (int k = 0; k < 10; ++k) {
      yaml += k > 0 ? ", k" : "k";
      yaml += std::to_string(k);
      yaml += ": ";
      yaml += previous;
    }
    yaml += "}\n";
  }
  yaml += "duration: 1\nsweep:\n  name: x\n  matrix: {integrator: [rk4], dt: [0.001]}\n";
  expect_error(yaml, "more than 100000 values (aliases expanded)");
}

TEST(SweepFile, SweepFilesAreToldApartFromSingleRunConfigs) {
  testing::ScratchFolder scratch;
  std::ofstream(scratch.path() / "sweep.yaml") << kValid;
  std::ofstream(scratch.path() / "single.yaml") << "integrator: rk4\ndt: 0.001\n";
  std::ofstream(scratch.path() / "broken.yaml") << "sweep: [\n";
  EXPECT_TRUE(is_sweep_file(scratch.path() / "sweep.yaml"));
  EXPECT_FALSE(is_sweep_file(scratch.path() / "single.yaml"));
  EXPECT_FALSE(is_sweep_file(scratch.path() / "broken.yaml"));
  EXPECT_FALSE(is_sweep_file(scratch.path() / "missing.yaml"));
  EXPECT_EQ(load_sweep(scratch.path() / "sweep.yaml").name, "tiny");
  EXPECT_THROW(load_sweep(scratch.path() / "missing.yaml"), host::InputError);
}

}  // namespace
}  // namespace clothlab::sweep
