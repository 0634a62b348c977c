// frame_rate / substeps, material.* and choose.* keys: how they resolve, and their one-line
// errors.
#include <gtest/gtest.h>
#include <unistd.h>

#include <clothlab/host/errors.hpp>
#include <filesystem>
#include <fstream>

#include "config_file.hpp"
#include "run_config.hpp"

namespace clothlab::cli {
namespace {

namespace fs = std::filesystem;

struct YamlFile {
  explicit YamlFile(const std::string& text)
      : path(fs::temp_directory_path() / ("clothlab_frames_" + std::to_string(getpid()) + "_" +
                                          std::to_string(next++) + ".yaml")) {
    std::ofstream(path) << text;
  }
  ~YamlFile() { fs::remove(path); }
  static inline int next = 0;
  fs::path path;
};

std::string error_of(const std::string& yaml) {
  const YamlFile file(yaml);
  try {
    resolve_run_config(read_config_file(file.path));
  } catch (const host::InputError& error) {
    // The temporary name varies; keep the position and the message.
    std::string text = error.what();
    const std::string name = file.path.string();
    for (size_t at = text.find(name); at != std::string::npos; at = text.find(name))
      text.replace(at, name.size(), "FILE");
    return text;
  }
  return "";
}

const char* cotton =
    "material:\n"
    "  name: cotton\n"
    "  areal_density: 0.15\n"
    "  stretch_stiffness: 6129\n"
    "  shear_stiffness: 44.95\n"
    "  bending_stiffness: 7.845e-6\n"
    "  damping_time: 1.0e-5\n";

TEST(Frames, StepIsOneOverFrameRateTimesSubsteps) {
  const YamlFile file("frame_rate: 60\nsubsteps: 4\nduration: 1\n");
  const RunConfig config = resolve_run_config(read_config_file(file.path));
  EXPECT_DOUBLE_EQ(config.dt, 1.0 / 240.0);
  EXPECT_EQ(config.substeps, 4u);
  EXPECT_EQ(config.steps, 240u);
}

TEST(Frames, WithoutFrameRateEveryStepIsAFrame) {
  const RunConfig config = resolve_run_config({{"dt", "0.002", "--dt"}});
  EXPECT_DOUBLE_EQ(config.frame_rate, 500.0);
  EXPECT_EQ(config.substeps, 1u);
}

TEST(Frames, BadFrameRateOrSubstepsNameFileKeyValueAndRange) {
  EXPECT_EQ(error_of("frame_rate: 0\n"),
            "FILE:1:13: frame_rate = 0: out of range; allowed: real in (0, 1e+06] Hz");
  EXPECT_EQ(error_of("frame_rate: -30\n"),
            "FILE:1:13: frame_rate = -30: out of range; allowed: real in (0, 1e+06] Hz");
  EXPECT_EQ(error_of("frame_rate: 60\nsubsteps: 0\n"),
            "FILE:2:11: substeps = 0: out of range; allowed: int in [1, 1e+06] steps per frame");
  EXPECT_EQ(error_of("frame_rate: 60\nsubsteps: -2\n"),
            "FILE:2:11: substeps = -2: out of range; allowed: int in [1, 1e+06] steps per frame");
  EXPECT_EQ(
      error_of("frame_rate: 60\nsubsteps: 2.5\n"),
      "FILE:2:11: substeps = 2.5: not a whole number; allowed: int in [1, 1e+06] steps per frame");
}

TEST(Frames, SubstepsNeedAFrameRateAndDtConflictsWithIt) {
  EXPECT_NE(error_of("substeps: 4\n").find("FILE:1:11: substeps = 4 without frame_rate"),
            std::string::npos);
  EXPECT_NE(error_of("dt: 0.001\nframe_rate: 60\n")
                .find("FILE:1:5: dt = 0.001 conflicts with FILE:2:13: frame_rate = 60"),
            std::string::npos);
}

// Below 2 the cost budget could stop a setting cheaper than the best (integrator_choice.hpp).
TEST(ChooseConfig, StopFactorIsZeroOrAtLeastTwo) {
  EXPECT_EQ(resolve_configuration({{"choose.stop_factor", "0", "--set"}}).choose.search.stop_factor,
            0.0);
  EXPECT_EQ(resolve_configuration({{"choose.stop_factor", "2", "--set"}}).choose.search.stop_factor,
            2.0);
  EXPECT_EQ(resolve_configuration({}).choose.search.stop_factor, 3.0);
  EXPECT_EQ(error_of("choose:\n  stop_factor: 1.5\n"),
            "FILE:2:16: choose.stop_factor = 1.5: out of range; allowed: 0 (no cost budget) or a "
            "real in [2, 1000]");
  EXPECT_EQ(error_of("choose:\n  stop_factor: -1\n"),
            "FILE:2:16: choose.stop_factor = -1: out of range; allowed: 0 (no cost budget) or a "
            "real in [2, 1000]");
}

TEST(Material, ResolvesEveryField) {
  const YamlFile file(cotton);
  const RunConfig config = resolve_run_config(read_config_file(file.path));
  ASSERT_TRUE(config.material.has_value());
  EXPECT_EQ(config.material->name, "cotton");
  EXPECT_DOUBLE_EQ(config.material->stretch_stiffness, 6129);
  EXPECT_DOUBLE_EQ(config.material->bending_stiffness, 7.845e-6);
}

TEST(Material, MissingFieldNamesFileKeyAndRange) {
  std::string yaml = cotton;
  yaml.erase(yaml.find("  bending_stiffness"),
             std::string("  bending_stiffness: 7.845e-6\n").size());
  EXPECT_EQ(error_of(yaml),
            "FILE:2:9: material cotton has no material.bending_stiffness; allowed: real in [0, 1] "
            "N m (a material sets every material.* value)");
}

TEST(Material, OutOfRangeFieldNamesFileLineColumnKeyValueAndRange) {
  std::string yaml = cotton;
  yaml.replace(yaml.find("0.15"), 4, "-0.15");
  EXPECT_EQ(error_of(yaml),
            "FILE:3:18: material.areal_density = -0.15: out of range; allowed: real in [1e-06, "
            "1000] kg/m^2");
  std::string stiff = cotton;
  stiff.replace(stiff.find("44.95"), 5, "7000");
  EXPECT_NE(error_of(stiff).find("material.shear_stiffness = 7000 N/m is not below "
                                 "material.stretch_stiffness = 6129 N/m"),
            std::string::npos);
}

}  // namespace
}  // namespace clothlab::cli
