// The scenario plugins' scenes: pins, layout axes, totals, gravity, wind only for the
// flag, the smallest grids, and parameter validation.
#include <gtest/gtest.h>

#include <algorithm>
#include <clothlab/host/plugin_library.hpp>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "param_values.hpp"

namespace clothlab::test {
namespace {

// A scenario instance described through the ABI; pinned indices copied out.
struct Described {
  clothlab_status status = CLOTHLAB_OK;
  std::string message;
  clothlab_scene scene{};
  std::vector<uint32_t> pinned;
};

Described describe(const std::string& path,
                   const std::vector<std::pair<std::string, clothlab_param_value>>& overrides) {
  const host::PluginLibrary library = host::PluginLibrary::load(path);
  const clothlab_scenario& scenario = library.scenario().descriptor();
  std::vector<clothlab_param_value> values = default_values(scenario.params, scenario.param_count);
  for (const auto& [name, value] : overrides) set_value(values, scenario.params, name, value);
  Described out;
  clothlab_message message{};
  void* instance = nullptr;
  out.status = scenario.create(values.data(), scenario.param_count, &instance, &message);
  if (out.status == CLOTHLAB_OK) {
    out.scene.struct_size = sizeof(clothlab_scene);
    out.status = scenario.describe(instance, &out.scene, &message);
    if (out.status == CLOTHLAB_OK)
      out.pinned.assign(out.scene.pinned, out.scene.pinned + out.scene.pinned_count);
    scenario.destroy(instance);
  }
  out.message = message.text;
  return out;
}

clothlab_param_value scalar(double value) { return {{value, 0.0, 0.0}}; }

Described grid(const std::string& path, uint32_t rows, uint32_t cols) {
  return describe(path, {{"rows", scalar(rows)}, {"cols", scalar(cols)}});
}

const std::string sheet = CLOTHLAB_TEST_SHEET_PLUGIN;
const std::string flag = CLOTHLAB_TEST_FLAG_PLUGIN;

double dot(const double* a, const double* b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

void expect_common_defaults(const Described& d) {
  ASSERT_EQ(d.status, CLOTHLAB_OK) << d.message;
  const clothlab_scene& s = d.scene;
  EXPECT_EQ(s.rows, 50u);
  EXPECT_EQ(s.cols, 50u);
  EXPECT_EQ(s.width, 1.0);
  EXPECT_EQ(s.height, 1.0);
  EXPECT_EQ(s.total_mass, 0.3);
  EXPECT_EQ(s.gravity[0], 0.0);
  EXPECT_EQ(s.gravity[1], -9.81);
  EXPECT_EQ(s.gravity[2], 0.0);
  // Hanging in the x-y plane: rows go down (-y), columns along +x, both unit.
  EXPECT_EQ(s.col_axis[0], 1.0);
  EXPECT_EQ(s.row_axis[1], -1.0);
  EXPECT_DOUBLE_EQ(dot(s.col_axis, s.col_axis), 1.0);
  EXPECT_DOUBLE_EQ(dot(s.row_axis, s.row_axis), 1.0);
  EXPECT_EQ(dot(s.col_axis, s.row_axis), 0.0);
  for (const clothlab_spring_family& family : {s.structural, s.shear, s.flexion}) {
    EXPECT_GT(family.ks, 0.0);
    EXPECT_GT(family.kd, 0.0);
  }
}

TEST(SheetScenario, PinsTopCornersUnderGravityWithoutWind) {
  const Described d = describe(sheet, {});
  expect_common_defaults(d);
  EXPECT_EQ(d.pinned, (std::vector<uint32_t>{0, 49}));
  EXPECT_EQ(d.scene.wind_strength, 0.0);
  // Top edge (row 0) is the highest; the line is centred on x = 0.
  EXPECT_EQ(d.scene.origin[0], -0.5);
  EXPECT_EQ(d.scene.origin[1], 1.0);
}

TEST(FlagScenario, PinsTheLeftColumnAndBlowsAcrossTheCloth) {
  const Described d = describe(flag, {});
  expect_common_defaults(d);
  std::vector<uint32_t> left_column;
  for (uint32_t row = 0; row < 50; ++row) left_column.push_back(row * 50);
  EXPECT_EQ(d.pinned, left_column);
  EXPECT_EQ(d.scene.wind_strength, 5.0);
  EXPECT_NEAR(dot(d.scene.wind_direction, d.scene.wind_direction), 1.0, 1e-15);
  // The cloth normal is col_axis x row_axis = (1,0,0) x (0,-1,0) = (0,0,-1): the wind
  // must have a component along it or a flat flag never moves.
  EXPECT_GT(std::abs(d.scene.wind_direction[2]), 0.1);
  EXPECT_NEAR(d.scene.wind_direction[0], 2.0 / std::sqrt(5.0), 1e-15);
}

TEST(FlagScenario, ZeroStrengthMeansNoWindStage) {
  const Described d = describe(flag, {{"wind.strength", scalar(0.0)}});
  ASSERT_EQ(d.status, CLOTHLAB_OK) << d.message;
  EXPECT_EQ(d.scene.wind_strength, 0.0);
}

TEST(FlagScenario, NormalisesTheWindDirection) {
  const Described d = describe(flag, {{"wind.direction", {{0.0, 0.0, -4.0}}}});
  ASSERT_EQ(d.status, CLOTHLAB_OK) << d.message;
  EXPECT_EQ(d.scene.wind_direction[2], -1.0);
}

TEST(FlagScenario, RejectsAZeroWindDirectionWhenThereIsWind) {
  const Described d = describe(flag, {{"wind.direction", {{0.0, 0.0, 0.0}}}});
  EXPECT_EQ(d.status, CLOTHLAB_ERROR_INVALID_ARGUMENT);
  EXPECT_NE(d.message.find("wind.direction"), std::string::npos) << d.message;
}

TEST(SmallGrids, OneByOneIsASinglePinnedPoint) {
  for (const std::string& path : {sheet, flag}) {
    const Described d = grid(path, 1, 1);
    ASSERT_EQ(d.status, CLOTHLAB_OK) << d.message;
    EXPECT_EQ(d.pinned, (std::vector<uint32_t>{0})) << path;
  }
}

TEST(SmallGrids, SheetTwoRowsOneColumnIsASingleHangingSpring) {
  const Described d = grid(sheet, 2, 1);
  ASSERT_EQ(d.status, CLOTHLAB_OK) << d.message;
  EXPECT_EQ(d.scene.rows, 2u);
  EXPECT_EQ(d.scene.cols, 1u);
  EXPECT_EQ(d.pinned, (std::vector<uint32_t>{0}));
}

TEST(SmallGrids, FlagTwoRowsOneColumnIsAllPole) {
  const Described d = grid(flag, 2, 1);
  ASSERT_EQ(d.status, CLOTHLAB_OK) << d.message;
  EXPECT_EQ(d.pinned, (std::vector<uint32_t>{0, 1}));
}

TEST(SmallGrids, OneRowTwoColumns) {
  EXPECT_EQ(grid(sheet, 1, 2).pinned, (std::vector<uint32_t>{0, 1}));
  EXPECT_EQ(grid(flag, 1, 2).pinned, (std::vector<uint32_t>{0}));
}

TEST(SmallGrids, OneByOneUnanchoredIsFreeFall) {
  for (const std::string& path : {sheet, flag}) {
    const Described d =
        describe(path, {{"rows", scalar(1)}, {"cols", scalar(1)}, {"anchored", scalar(0)}});
    ASSERT_EQ(d.status, CLOTHLAB_OK) << d.message;
    EXPECT_TRUE(d.pinned.empty()) << path;
    EXPECT_EQ(d.scene.pinned_count, 0u);
  }
}

TEST(ScenarioParameters, AnchoredMustBeABoolean) {
  EXPECT_EQ(describe(sheet, {{"anchored", scalar(2)}}).status, CLOTHLAB_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(describe(flag, {{"anchored", scalar(0.5)}}).status, CLOTHLAB_ERROR_INVALID_ARGUMENT);
}

TEST(ScenarioParameters, DeclareTheIssueKeys) {
  const std::vector<std::string> common{"rows",     "cols",          "width",         "height",
                                        "mass",     "structural.ks", "structural.kd", "shear.ks",
                                        "shear.kd", "flexion.ks",    "flexion.kd",    "gravity",
                                        "anchored"};
  for (const std::string& path : {sheet, flag}) {
    const host::PluginLibrary library = host::PluginLibrary::load(path);
    const clothlab_scenario& scenario = library.scenario().descriptor();
    std::vector<std::string> names;
    for (uint32_t i = 0; i < scenario.param_count; ++i) names.push_back(scenario.params[i].name);
    std::vector<std::string> expected = common;
    if (path == flag)
      expected.insert(expected.end(), {"wind.direction", "wind.strength", "air.density",
                                       "air.speed", "air.drag", "air.lift"});
    EXPECT_EQ(names, expected) << path;
  }
}

TEST(ScenarioParameters, OutOfRangeValuesAreRejectedByName) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const std::vector<std::pair<std::string, clothlab_param_value>> bad{
      {"rows", scalar(0)},        {"cols", scalar(0)},         {"rows", scalar(4097)},
      {"rows", scalar(2.5)},      {"width", scalar(0)},        {"height", scalar(-1)},
      {"mass", scalar(0)},        {"mass", scalar(nan)},       {"structural.ks", scalar(-1)},
      {"shear.kd", scalar(-0.1)}, {"flexion.ks", scalar(nan)}, {"gravity", {{0, nan, 0}}},
      {"gravity", {{0, -1e4, 0}}}};
  for (const std::string& path : {sheet, flag})
    for (const auto& [name, value] : bad) {
      const Described d = describe(path, {{name, value}});
      EXPECT_EQ(d.status, CLOTHLAB_ERROR_INVALID_ARGUMENT) << path << " " << name;
      EXPECT_NE(d.message.find(name), std::string::npos) << d.message;
    }
  EXPECT_EQ(describe(flag, {{"wind.strength", scalar(-1)}}).status,
            CLOTHLAB_ERROR_INVALID_ARGUMENT);
}

TEST(ScenarioParameters, LargestGridIsAccepted) {
  const Described d = grid(sheet, 4096, 3);
  ASSERT_EQ(d.status, CLOTHLAB_OK) << d.message;
  EXPECT_EQ(d.scene.rows, 4096u);
}

TEST(ScenarioDescribe, RejectsATooSmallSceneBuffer) {
  const host::PluginLibrary library = host::PluginLibrary::load(sheet);
  const clothlab_scenario& scenario = library.scenario().descriptor();
  const auto values = default_values(scenario.params, scenario.param_count);
  void* instance = nullptr;
  clothlab_message message{};
  ASSERT_EQ(scenario.create(values.data(), scenario.param_count, &instance, &message), CLOTHLAB_OK);
  clothlab_scene scene{};
  scene.struct_size = sizeof(clothlab_scene) - 8;
  EXPECT_EQ(scenario.describe(instance, &scene, &message), CLOTHLAB_ERROR_INVALID_ARGUMENT);
  scenario.destroy(instance);
}

}  // namespace
}  // namespace clothlab::test
