// A small horizontal cloth above one collider whose every field is a parameter, with ranges
// wide enough to let malformed values through to the host's checks of clothlab.colliders/1.
#include <array>
#include <clothlab/sdk.hpp>
#include <cmath>
#include <span>

namespace {

using clothlab::sdk::int_param;
using clothlab::sdk::real_param;

struct ColliderScene {
  static constexpr const char* id = "test-collider";
  static constexpr const char* name = "Test collider";
  static constexpr const char* version = "0.1.0";
  static constexpr const char* description =
      "a small flat cloth dropped onto one collider; for host tests";
  static constexpr std::array params{
      int_param("rows", 3, 1, 8, "particle rows"),
      int_param("cols", 3, 1, 8, "particle columns"),
      real_param("height", 0.3, 0.0, 10.0, "m", "the cloth's start height above the origin"),
      int_param("shape", CLOTHLAB_COLLIDER_PLANE, 0, 9, "clothlab_collider shape code"),
      real_param("radius", 0.2, -1.0, 10.0, "m", "sphere or capsule radius"),
      real_param("half_length", 0.5, -1.0, 10.0, "m", "capsule half length"),
      real_param("friction", 0.5, -1.0, 10.0, "", "Coulomb coefficient"),
      real_param("thickness", 0.01, -1.0, 1.0, "m", "contact thickness"),
      real_param("broken_pose_after", -1.0, -1.0, 1e9, "s",
                 "from this time on the pose is not finite; -1 never"),
      real_param("jump_after", -1.0, -1.0, 1e9, "s",
                 "from this time on the collider is 2 m to the side; -1 never"),
  };

  explicit ColliderScene(const clothlab::sdk::Params& values)
      : rows_(static_cast<uint32_t>(values.integer("rows"))),
        cols_(static_cast<uint32_t>(values.integer("cols"))),
        height_(values.real("height")),
        broken_after_(values.real("broken_pose_after")),
        jump_after_(values.real("jump_after")) {
    collider_.struct_size = sizeof collider_;
    collider_.shape = static_cast<uint32_t>(values.integer("shape"));
    collider_.radius = collider_.end_radius = values.real("radius");
    collider_.half_length = values.real("half_length");
    collider_.half_extents[0] = collider_.half_extents[1] = collider_.half_extents[2] = 0.5;
    collider_.friction = values.real("friction");
    collider_.thickness = values.real("thickness");
  }

  void describe(clothlab_scene& scene) const {
    scene.rows = rows_;
    scene.cols = cols_;
    scene.width = 0.2;
    scene.height = 0.2;
    scene.origin[1] = height_;
    scene.col_axis[0] = 1.0;
    scene.row_axis[2] = 1.0;
    scene.total_mass = 0.01;
    scene.structural = {5.0, 0.005};
    scene.gravity[1] = -9.81;
  }

  std::span<const clothlab_collider> colliders() const { return {&collider_, 1}; }
  clothlab_pose collider_pose(uint32_t, double t) const {
    clothlab_pose pose{{0, 0, 0}, {1, 0, 0, 0}};
    if (broken_after_ >= 0 && t >= broken_after_) pose.position[0] = NAN;
    if (jump_after_ >= 0 && t >= jump_after_) pose.position[0] = 2.0;
    return pose;
  }

 private:
  uint32_t rows_, cols_;
  double height_, broken_after_, jump_after_;
  clothlab_collider collider_{};
};

}  // namespace

CLOTHLAB_PLUGIN_ENTRY("clothlab-test-collider", "0.1.0", clothlab::sdk::integrators<>,
                      clothlab::sdk::scenarios<ColliderScene>)
