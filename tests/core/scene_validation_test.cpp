#include <gtest/gtest.h>

#include <clothlab/core/cloth.hpp>
#include <cmath>
#include <functional>
#include <limits>
#include <stdexcept>
#include <string>

namespace clothlab {
namespace {

const uint32_t kPins[] = {0, 2, 2, 0};

clothlab_scene valid_scene() {
  clothlab_scene scene{};
  scene.struct_size = sizeof scene;
  scene.rows = 3;
  scene.cols = 2;
  scene.pinned_count = 4;
  scene.pinned = kPins;
  scene.width = 1.0;
  scene.height = 2.0;
  scene.col_axis[0] = 1.0;
  scene.row_axis[1] = -1.0;
  scene.total_mass = 0.5;
  scene.structural = {100.0, 1.0};
  scene.gravity[1] = -9.81;
  scene.wind_direction[2] = 1.0;
  scene.wind_strength = 2.0;
  return scene;
}

// The error message of scene_from_abi after `edit`, or "" when it accepted the scene.
std::string rejection(const std::function<void(clothlab_scene&)>& edit) {
  clothlab_scene scene = valid_scene();
  edit(scene);
  try {
    scene_from_abi(scene);
  } catch (const std::invalid_argument& error) {
    return error.what();
  }
  return "";
}

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

TEST(SceneValidation, AcceptsAValidScene) {
  const Scene scene = scene_from_abi(valid_scene());
  EXPECT_EQ(scene.rows, 3u);
  EXPECT_EQ(scene.cols, 2u);
  EXPECT_EQ(scene.pinned, (std::vector<uint32_t>{0, 2}));  // sorted, duplicates removed
  EXPECT_EQ(scene.col_axis, (Vec3{1, 0, 0}));
  EXPECT_EQ(scene.row_axis, (Vec3{0, -1, 0}));
  EXPECT_EQ(scene.wind_direction, (Vec3{0, 0, 1}));
  EXPECT_EQ(scene.structural.ks, 100.0);
  EXPECT_EQ(scene.gravity, (Vec3{0, -9.81, 0}));
}

TEST(SceneValidation, WindDirectionIgnoredWithoutWind) {
  clothlab_scene abi = valid_scene();
  abi.wind_strength = 0.0;
  abi.wind_direction[2] = 0.0;
  EXPECT_FALSE(scene_from_abi(abi).has_wind());
}

TEST(SceneValidation, FieldsBeyondStructSizeAreNotRead) {
  clothlab_scene abi = valid_scene();
  abi.struct_size = offsetof(clothlab_scene, gravity);
  abi.gravity[0] = kNaN;     // beyond struct_size: must not be seen
  abi.wind_strength = -1.0;  // likewise
  const Scene scene = scene_from_abi(abi);
  EXPECT_EQ(scene.gravity, (Vec3{0, 0, 0}));
  EXPECT_FALSE(scene.has_wind());
}

TEST(SceneValidation, RejectsEachBadField) {
  struct Case {
    std::function<void(clothlab_scene&)> edit;
    std::string expected;
  };
  const Case cases[] = {
      {[](clothlab_scene& s) { s.rows = 0; }, "scene.rows = 0: allowed integer >= 1"},
      {[](clothlab_scene& s) { s.cols = 0; }, "scene.cols = 0: allowed integer >= 1"},
      {[](clothlab_scene& s) { s.width = -1; }, "scene.width = -1: allowed finite > 0"},
      {[](clothlab_scene& s) { s.height = kNaN; }, "scene.height = nan: allowed finite > 0"},
      {[](clothlab_scene& s) { s.total_mass = 0; }, "scene.total_mass = 0: allowed finite > 0"},
      {[](clothlab_scene& s) { s.structural.ks = -2; },
       "scene.structural.ks = -2: allowed finite >= 0"},
      {[](clothlab_scene& s) { s.shear.kd = kInf; }, "scene.shear.kd = inf: allowed finite >= 0"},
      {[](clothlab_scene& s) { s.flexion.ks = kNaN; },
       "scene.flexion.ks = nan: allowed finite >= 0"},
      {[](clothlab_scene& s) { s.col_axis[0] = 0; },
       "scene.col_axis = (0, 0, 0): allowed a unit vector"},
      {[](clothlab_scene& s) { s.row_axis[2] = kInf; },
       "scene.row_axis = (0, -1, inf): allowed finite components"},
      {[](clothlab_scene& s) { s.origin[1] = kNaN; },
       "scene.origin = (0, nan, 0): allowed finite components"},
      {[](clothlab_scene& s) { s.gravity[2] = kNaN; },
       "scene.gravity = (0, -9.8100000000000005, nan): allowed finite components"},
      {[](clothlab_scene& s) { s.wind_strength = -0.5; },
       "scene.wind_strength = -0.5: allowed finite >= 0"},
      {[](clothlab_scene& s) { s.wind_direction[2] = 0; },
       "scene.wind_direction = (0, 0, 0): allowed a unit vector"},
  };
  for (std::size_t c = 0; c < std::size(cases); ++c) {
    const std::string message = rejection(cases[c].edit);
    EXPECT_EQ(message.substr(0, cases[c].expected.size()), cases[c].expected)
        << "case " << c << ": " << message;
  }
}

// The core and the conformance runner disagreed on these (issue 12): the header's contract
// (unit axes, not parallel; spacing only where there are two particles) is the one rule.
TEST(SceneValidation, FollowsTheHeadersContract) {
  EXPECT_EQ(rejection([](clothlab_scene& s) { s.col_axis[0] = 2.0; }),
            "scene.col_axis = (2, 0, 0): allowed a unit vector");
  EXPECT_EQ(rejection([](clothlab_scene& s) {
              s.row_axis[0] = 1.0;
              s.row_axis[1] = 0.0;
            }),
            "scene.row_axis = (1, 0, 0): allowed not parallel to col_axis (1, 0, 0)");
  EXPECT_EQ(rejection([](clothlab_scene& s) { s.wind_direction[2] = 5.0; }),
            "scene.wind_direction = (0, 0, 5): allowed a unit vector");
  EXPECT_EQ(rejection([](clothlab_scene& s) {
              s.cols = 1;
              s.width = 0.0;
            }),
            "");
  EXPECT_EQ(rejection([](clothlab_scene& s) { s.width = 0.0; }),
            "scene.width = 0: allowed finite > 0");
}

TEST(SceneValidation, RejectsPinsOutsideTheGrid) {
  static const uint32_t outside[] = {1, 6};
  const std::string message = rejection([](clothlab_scene& s) {
    s.pinned = outside;
    s.pinned_count = 2;
  });
  EXPECT_EQ(message, "scene.pinned = 6: allowed indices < rows*cols = 6");
}

TEST(SceneValidation, RejectsMissingPinArray) {
  const std::string message = rejection([](clothlab_scene& s) { s.pinned = nullptr; });
  EXPECT_EQ(message.rfind("scene.pinned = NULL", 0), 0u) << message;
}

TEST(SceneValidation, RejectsTruncatedStruct) {
  const std::string message = rejection([](clothlab_scene& s) { s.struct_size = 8; });
  EXPECT_EQ(message.rfind("scene.struct_size = 8", 0), 0u) << message;
}

}  // namespace
}  // namespace clothlab

namespace clothlab {
namespace {

// clothlab.air/1's fields: one line naming the field, the value and what is allowed.
TEST(AirValidation, RejectsEachBadFieldAndAcceptsNoAir) {
  const auto rejection_of = [](const std::function<void(clothlab_air&)>& edit) -> std::string {
    clothlab_air air{};
    air.struct_size = sizeof air;
    air.density = 1.225;
    air.drag_coefficient = 1.0;
    edit(air);
    try {
      air_from_abi(air);
    } catch (const std::invalid_argument& error) {
      return error.what();
    }
    return "";
  };
  EXPECT_EQ(rejection_of([](clothlab_air&) {}), "");
  EXPECT_EQ(rejection_of([](clothlab_air& air) { air.density = -1.0; }),
            "air.density = -1: allowed finite >= 0");
  EXPECT_EQ(rejection_of([](clothlab_air& air) { air.drag_coefficient = kNaN; }),
            "air.drag_coefficient = nan: allowed finite >= 0");
  EXPECT_EQ(rejection_of([](clothlab_air& air) { air.lift_coefficient = -0.5; }),
            "air.lift_coefficient = -0.5: allowed finite >= 0");
  EXPECT_EQ(rejection_of([](clothlab_air& air) { air.wind_velocity[1] = kInf; }),
            "air.wind_velocity = (0, inf, 0): allowed finite components");
  EXPECT_EQ(rejection_of([](clothlab_air& air) { air.struct_size = 8; }),
            "air.struct_size = 8: allowed >= " + std::to_string(sizeof(clothlab_air)));
  clothlab_air none{};
  none.struct_size = sizeof none;
  Scene scene;
  scene.air = air_from_abi(none);
  EXPECT_FALSE(scene.has_air());
}

TEST(ClothConstruction, RejectsWhatValidationWouldHave) {
  Scene scene;
  scene.rows = 2;
  scene.cols = 2;
  scene.pinned = {4};
  EXPECT_THROW(Cloth(scene, Precision::Float32, {}), std::invalid_argument);
  scene.pinned.clear();
  scene.cols = 0;
  EXPECT_THROW(Cloth(scene, Precision::Float64, {}), std::invalid_argument);
  scene.cols = 2;
  PipelineOptions options;
  options.threads = -1;
  EXPECT_THROW(Cloth(scene, Precision::Float64, options), std::invalid_argument);
}

TEST(ClothConstruction, ReportsTheThreadsItUses) {
  PipelineOptions options;
  options.threads = 3;
  EXPECT_EQ(Cloth(Scene{}, Precision::Float32, options).threads(), 1);  // too small to split
  Scene large;
  large.rows = 100;
  large.cols = 100;
  EXPECT_EQ(Cloth(large, Precision::Float32, options).threads(), 3);
  EXPECT_GE(Cloth(large, Precision::Float32, {}).threads(), 1);  // 0: all hardware threads
}

TEST(ClothConstruction, SetStateRejectsWrongSizes) {
  Cloth cloth(Scene{}, Precision::Float64, {});
  EXPECT_THROW(cloth.set_state({0, 0}, {0, 0, 0}), std::invalid_argument);
}

}  // namespace
}  // namespace clothlab
