// Drape test (after Cusick's drape meter): a square cloth, level and centred, falls from just
// above a support, a sphere or a table (box), and settles over it under gravity and friction.
// The support may move at a constant velocity (clothlab.colliders/2): a table sliding under the
// cloth carries it by friction; a thin one rising fast (a blade) must not pass through it.
// The host reports the drape coefficient, the share of the cloth's area its shadow keeps
// (clothlab.colliders/1 scenes: the run JSON's `contacts`). `anchored` pins the cloth's centre
// particle, as the drape meter clamps the specimen's centre between two discs.
//
// Frame: the support's top is at the origin and y is up. The sphere's centre is at
// (0, -radius, 0); the table is a box of half width and half height `support.size`, the blade
// a box of half width `support.size` and a thousandth of that half height (2 mm thick for a 1 m
// half width), each with its top face at y = 0; all at t = 0, then moving at `support.velocity`.
#include <clothlab/ext/colliders.h>

#include <array>
#include <clothlab/sdk.hpp>
#include <span>
#include <vector>

#include "grid_cloth.hpp"

namespace clothlab::builtin {

inline constexpr double support_sphere = 0, support_box = 1, support_blade = 2;
inline constexpr double blade_thinness = 1e-3;  // half height / half width

struct Drape {
  static constexpr const char* id = "drape";
  static constexpr const char* name = "Drape over a sphere or a table";
  static constexpr const char* version = "1.0.0";
  static constexpr const char* description =
      "Square cloth dropped level onto a sphere or a box with friction; settles into a drape";
  static constexpr auto params =
      concat(grid_cloth_params(),
             std::array{
                 sdk::int_param("support", support_sphere, support_sphere, support_blade,
                                "what the cloth falls on: 0 = sphere, 1 = table (box), 2 = blade "
                                "(a box a thousandth as high as wide)"),
                 sdk::real_param("support.size", 0.3, 1e-3, 1e3, "m",
                                 "the sphere's radius, or the table's or blade's half width"),
                 sdk::vec3_param("support.velocity", {0.0, 0.0, 0.0}, -100.0, 100.0, "m/s",
                                 "the support's constant velocity from t = 0"),
                 sdk::real_param("friction", 0.5, 0.0, 10.0, "",
                                 "Coulomb coefficient between the cloth and the support"),
                 sdk::real_param("thickness", 0.005, 0.0, 0.1, "m",
                                 "distance the cloth is kept from the support's surface"),
                 sdk::real_param("drop", 0.05, 0.0, 100.0, "m",
                                 "the cloth's start height above the support's top"),
             });

  explicit Drape(const sdk::Params& values) : cloth_(values), drop_(values.real("drop")) {
    if (cloth_.anchored) pinned_.push_back((cloth_.rows / 2) * cloth_.cols + cloth_.cols / 2);
    const double size = values.real("support.size");
    support_.struct_size = sizeof support_;
    support_.friction = values.real("friction");
    support_.thickness = values.real("thickness");
    if (values.integer("support") == support_sphere) {
      support_.shape = CLOTHLAB_COLLIDER_SPHERE;
      support_.radius = size;
      centre_ = {0.0, -size, 0.0};
    } else {
      support_.shape = CLOTHLAB_COLLIDER_BOX;
      const double half_height =
          values.integer("support") == support_blade ? blade_thinness * size : size;
      support_.half_extents[0] = support_.half_extents[2] = size;
      support_.half_extents[1] = half_height;
      centre_ = {0.0, -half_height, 0.0};
    }
    velocity_ = values.vec3("support.velocity");
  }

  void describe(clothlab_scene& scene) const {
    cloth_.fill(scene);
    // Level in the x-z plane, centred over the support, `thickness + drop` above its top.
    set_vec3(scene.origin, -0.5 * cloth_.width, support_.thickness + drop_, -0.5 * cloth_.height);
    set_vec3(scene.col_axis, 1.0, 0.0, 0.0);
    set_vec3(scene.row_axis, 0.0, 0.0, 1.0);
    scene.pinned_count = static_cast<uint32_t>(pinned_.size());
    scene.pinned = pinned_.data();
  }

  std::span<const clothlab_collider> colliders() const { return {&support_, 1}; }
  clothlab_collider_motion collider_motion(uint32_t, double t) const {
    clothlab_collider_motion out{};
    for (int k = 0; k < 3; ++k) {
      out.pose.position[k] = centre_[k] + velocity_[k] * t;
      out.velocity[k] = velocity_[k];
    }
    out.pose.orientation[0] = 1.0;
    return out;
  }

 private:
  GridCloth cloth_;
  double drop_;
  clothlab_collider support_{};
  std::array<double, 3> centre_{};
  std::array<double, 3> velocity_{};
  std::vector<uint32_t> pinned_;
};

}  // namespace clothlab::builtin

CLOTHLAB_PLUGIN_ENTRY("clothlab-builtin-drape", "1.0.0", clothlab::sdk::integrators<>,
                      clothlab::sdk::scenarios<clothlab::builtin::Drape>)
