// A small hanging cloth whose first top particle is attached to a point going round a circle
// (clothlab.attachments/1), with ways to break the path: for host tests of the attachments.
#include <array>
#include <clothlab/sdk.hpp>
#include <cmath>
#include <span>

namespace {

using clothlab::sdk::int_param;
using clothlab::sdk::real_param;

struct AttachmentScene {
  static constexpr const char* id = "test-attachment";
  static constexpr const char* name = "Test attachment";
  static constexpr const char* version = "0.1.0";
  static constexpr const char* description =
      "a small cloth hanging from a particle that goes round a circle; for host tests";
  static constexpr std::array params{
      int_param("particle", 0, 0, 1000, "the attached particle (the grid has 3 x 3)"),
      real_param("radius", 0.1, 0.0, 10.0, "m", "the circle's radius"),
      real_param("omega", 3.0, 0.0, 100.0, "rad/s", "the angular speed on the circle"),
      real_param("broken_after", -1.0, -1.0, 1e9, "s",
                 "from this time on the target is not finite; -1 never"),
      real_param("jump_at", -1.0, -1.0, 1e9, "s",
                 "from this time on the target is 1 m further along x; -1 never"),
  };

  explicit AttachmentScene(const clothlab::sdk::Params& values)
      : particle_(static_cast<uint32_t>(values.integer("particle"))),
        radius_(values.real("radius")),
        omega_(values.real("omega")),
        broken_after_(values.real("broken_after")),
        jump_at_(values.real("jump_at")) {}

  void describe(clothlab_scene& scene) const {
    scene.rows = 3;
    scene.cols = 3;
    scene.width = 0.2;
    scene.height = 0.2;
    scene.col_axis[0] = 1.0;
    scene.row_axis[1] = -1.0;
    scene.total_mass = 0.01;
    scene.structural = {5.0, 0.005};
    scene.shear = {2.0, 0.002};
    scene.gravity[1] = -9.81;
  }

  // The circle in the x-y plane through the origin (the grid's top-left corner) at t = 0.
  static std::array<double, 6> path(double radius, double omega, double t) {
    const double c = std::cos(omega * t), s = std::sin(omega * t);
    return {radius * (c - 1.0), radius * s, 0.0, -radius * omega * s, radius * omega * c, 0.0};
  }

  std::span<const uint32_t> attached_particles() const { return {&particle_, 1}; }
  void attachment_targets(double t, std::span<double> positions,
                          std::span<double> velocities) const {
    const std::array<double, 6> target = path(radius_, omega_, t);
    for (int axis = 0; axis < 3; ++axis) {
      positions[axis] = target[axis];
      velocities[axis] = target[3 + axis];
    }
    if (jump_at_ >= 0 && t >= jump_at_) positions[0] += 1.0;
    if (broken_after_ >= 0 && t >= broken_after_) positions[1] = NAN;
  }

 private:
  uint32_t particle_;
  double radius_, omega_, broken_after_, jump_at_;
};

}  // namespace

CLOTHLAB_PLUGIN_ENTRY("clothlab-test-attachment", "0.1.0", clothlab::sdk::integrators<>,
                      clothlab::sdk::scenarios<AttachmentScene>)
