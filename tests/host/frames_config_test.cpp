// The frames.* keys: --frames, frames.every | frames.rate, frames.format.
#include <gtest/gtest.h>

#include <clothlab/host/errors.hpp>

#include "command_line.hpp"
#include "run_config.hpp"

namespace clothlab::cli {
namespace {

std::string error_of(const std::vector<Setting>& settings) {
  try {
    resolve_run_config(settings);
  } catch (const host::InputError& error) {
    return error.what();
  }
  return "";
}

TEST(FramesConfig, DefaultIsSixtyFramesPerSimulatedSecondAsVtp) {
  const RunConfig run = resolve_run_config({{"dt", "0.001", "--dt"}});
  EXPECT_TRUE(run.frames.dir.empty());
  EXPECT_EQ(run.frames.every_steps, 17u);  // 1 / (60 Hz * 1 ms) = 16.7, to the nearest step
  EXPECT_EQ(run.frames.formats, std::vector<std::string>{"vtp"});
}

TEST(FramesConfig, FramesFlagRateEveryAndFormats) {
  const char* argv[] = {"clothlab",
                        "--frames",
                        "out/frames",
                        "--set",
                        "frames.rate=30",
                        "--set",
                        "frames.format=[obj, pc2]"};
  const CommandLine command_line = parse_command_line(7, argv);
  RunConfig run = resolve_run_config(command_line.settings);
  EXPECT_EQ(run.frames.dir, "out/frames");
  EXPECT_EQ(run.frames.every_steps, 33u);
  EXPECT_EQ(run.frames.formats, (std::vector<std::string>{"obj", "pc2"}));
  // The later of every and rate wins, as steps and duration do.
  run = resolve_run_config({{"frames.rate", "30", "a"}, {"frames.every", "5", "b"}});
  EXPECT_EQ(run.frames.every_steps, 5u);
  run = resolve_run_config({{"frames.every", "5", "a"}, {"frames.rate", "1000", "b"}});
  EXPECT_EQ(run.frames.every_steps, 1u);  // faster than the step: every step
}

TEST(FramesConfig, FollowTheRunsFrameRateUnlessFramesRateIsGiven) {
  RunConfig run = resolve_run_config({{"frame_rate", "30", "a"}, {"substeps", "10", "b"}});
  EXPECT_EQ(run.frames.every_steps, 10u);  // one frame per frame_rate frame
  run = resolve_run_config(
      {{"frame_rate", "30", "a"}, {"substeps", "10", "b"}, {"frames.rate", "15", "c"}});
  EXPECT_EQ(run.frames.every_steps, 20u);
}

TEST(FramesConfig, BadValuesNameSourceKeyValueAndAllowed) {
  EXPECT_EQ(error_of({{"frames.format", "[vtp, gltf]", "x.yaml:3:9"}}),
            "x.yaml:3:9: frames.format = [vtp, gltf]: unknown value 'gltf'; allowed: vtp, obj or "
            "pc2, or a list of them, e.g. [vtp, obj]");
  EXPECT_EQ(error_of({{"frames.format", "[vtp, vtp]", "--set"}}),
            "--set: frames.format = [vtp, vtp]: repeats vtp; allowed: vtp, obj or pc2, or a list "
            "of them, e.g. [vtp, obj]");
  EXPECT_EQ(error_of({{"frames.every", "0", "--set"}}),
            "--set: frames.every = 0: out of range; allowed: int in [1, 1e+09] steps");
  EXPECT_EQ(error_of({{"frames.rate", "-60", "--set"}}).rfind("--set: frames.rate = -60: ", 0), 0u);
  EXPECT_EQ(error_of({{"frames.dir", "", "--frames"}}),
            "--frames: frames.dir is empty; allowed: a folder path");
}

}  // namespace
}  // namespace clothlab::cli
