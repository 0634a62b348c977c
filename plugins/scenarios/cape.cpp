// A cape on a walking, turning and running character (issue 22): a cloth attached by its top
// edge to the shoulders of a character made of capsules (a tapered torso, a shoulder bar and
// two upper arms) that follows a scripted loop: it starts walking, walks, turns while walking,
// speeds up to a run, runs, stops and stands, then does it all again from where it stands.
// The speed is continuous (linear ramps), the path too (arcs at constant speed in the turns),
// so the attachments' targets (clothlab.attachments/1) and the colliders' poses
// (clothlab.colliders/1) are continuous in position and the character's velocity. The cape
// moves through air (clothlab.air/1, drag and lift from the air's velocity relative to each
// triangle; still air by default), which makes it stream behind the running character; the
// coefficients are the flag's round illustrative values.
//
// Frame: y is up and the character starts at the origin facing +x; its body frame has x
// forward, y up and z to its right. The cape hangs behind the back, its top edge on the line
// x = -(torso.radius + thickness + back_gap), y = shoulder height, across z; rows go down.
#include <clothlab/ext/air.h>
#include <clothlab/ext/colliders.h>

#include <array>
#include <clothlab/sdk.hpp>
#include <cmath>
#include <numbers>
#include <span>
#include <string_view>
#include <vector>

#include "grid_cloth.hpp"

namespace clothlab::builtin {

namespace cape {

using Vec3 = std::array<double, 3>;

// The grid parameters with a cape's defaults: 0.5 m x 0.8 m of cotton (0.15 kg/m^2).
constexpr auto grid_params() {
  auto params = grid_cloth_params();
  const std::pair<std::string_view, double> defaults[] = {
      {"rows", 32}, {"cols", 20}, {"width", 0.5}, {"height", 0.8}, {"mass", 0.06}};
  for (auto& spec : params)
    for (const auto& [name, value] : defaults)
      if (std::string_view(spec.name) == name) spec.default_value[0] = value;
  return params;
}

// The gap between the torso's back (plus the contact thickness) and the cape's top edge.
inline constexpr double back_gap = 0.02;
inline constexpr double shoulder_height = 1.42;

// Rotation about +y by psi: body frame to world. Forward (1, 0, 0) goes to (cos, 0, -sin).
inline Vec3 yaw(double psi, const Vec3& b) {
  const double c = std::cos(psi), s = std::sin(psi);
  return {c * b[0] + s * b[2], b[1], -s * b[0] + c * b[2]};
}

// Quaternion product a b, (w, x, y, z).
inline std::array<double, 4> multiply(const std::array<double, 4>& a,
                                      const std::array<double, 4>& b) {
  return {a[0] * b[0] - a[1] * b[1] - a[2] * b[2] - a[3] * b[3],
          a[0] * b[1] + a[1] * b[0] + a[2] * b[3] - a[3] * b[2],
          a[0] * b[2] - a[1] * b[3] + a[2] * b[0] + a[3] * b[1],
          a[0] * b[3] + a[1] * b[2] - a[2] * b[1] + a[3] * b[0]};
}

// One piece of the script: the speed goes linearly from v0 to v1, or (turn != 0) stays v0 while
// the heading turns at a constant rate.
struct Segment {
  double duration, v0, v1, turn_rate;
  Vec3 start{};  // in the loop's frame
  double heading = 0;
};

// Where the character is, which way it faces, and how both change.
struct BodyState {
  Vec3 position, velocity;
  double heading, turn_rate;
};

class Script {
 public:
  explicit Script(const sdk::Params& values) {
    const double walk = values.real("walk.speed"), run = values.real("run.speed");
    const double angle = values.real("turn.angle") * std::numbers::pi / 180.0;
    const double turn = values.real("turn.duration");
    segments_ = {{values.real("start.duration"), 0.0, walk, 0.0},
                 {values.real("walk.duration"), walk, walk, 0.0},
                 {turn, walk, walk, angle / turn},
                 {values.real("speedup.duration"), walk, run, 0.0},
                 {values.real("run.duration"), run, run, 0.0},
                 {values.real("stop.duration"), run, 0.0, 0.0},
                 {values.real("rest.duration"), 0.0, 0.0, 0.0}};
    Vec3 position{};
    double heading = 0;
    for (Segment& segment : segments_) {
      segment.start = position;
      segment.heading = heading;
      const BodyState end = within(segment, segment.duration);
      position = end.position;
      heading = end.heading;
      loop_duration_ += segment.duration;
    }
    loop_shift_ = position;
    loop_turn_ = heading;
  }

  BodyState at(double t) const {
    // Whole loops first: each starts where the last ended, turned by the loop's heading change.
    Vec3 origin{};
    double heading = 0;
    const double loops = loop_duration_ > 0 ? std::floor(std::max(t, 0.0) / loop_duration_) : 0;
    for (double k = 0; k < loops; ++k) {
      const Vec3 shift = yaw(heading, loop_shift_);
      for (int axis = 0; axis < 3; ++axis) origin[axis] += shift[axis];
      heading += loop_turn_;
    }
    double local = std::max(t, 0.0) - loops * loop_duration_;
    const Segment* segment = &segments_.back();
    for (const Segment& candidate : segments_) {
      if (local <= candidate.duration) {
        segment = &candidate;
        break;
      }
      local -= candidate.duration;
    }
    BodyState state = within(*segment, std::min(local, segment->duration));
    const Vec3 position = yaw(heading, state.position);
    for (int axis = 0; axis < 3; ++axis) state.position[axis] = origin[axis] + position[axis];
    state.velocity = yaw(heading, state.velocity);
    state.heading += heading;
    return state;
  }

 private:
  // tau s into the segment, in the loop's frame.
  static BodyState within(const Segment& segment, double tau) {
    BodyState state{segment.start, {}, segment.heading, segment.turn_rate};
    if (segment.turn_rate == 0.0) {
      // A straight segment may last 0 s (walk.duration, run.duration = 0); only the ramps,
      // at least 0.01 s long, divide by their duration.
      const double acceleration =
          segment.v1 == segment.v0 ? 0.0 : (segment.v1 - segment.v0) / segment.duration;
      const double covered = segment.v0 * tau + acceleration * tau * tau / 2.0;
      const double speed = segment.v0 + acceleration * tau;
      const Vec3 forward = yaw(segment.heading, {1.0, 0.0, 0.0});
      for (int axis = 0; axis < 3; ++axis) {
        state.position[axis] += covered * forward[axis];
        state.velocity[axis] = speed * forward[axis];
      }
      return state;
    }
    // An arc at constant speed: the integral of v0 (cos psi, 0, -sin psi) over the heading.
    const double w = segment.turn_rate, psi = segment.heading + w * tau;
    state.heading = psi;
    state.position[0] += segment.v0 / w * (std::sin(psi) - std::sin(segment.heading));
    state.position[2] += segment.v0 / w * (std::cos(psi) - std::cos(segment.heading));
    const Vec3 forward = yaw(psi, {1.0, 0.0, 0.0});
    for (int axis = 0; axis < 3; ++axis) state.velocity[axis] = segment.v0 * forward[axis];
    return state;
  }

  std::vector<Segment> segments_;
  double loop_duration_ = 0;
  Vec3 loop_shift_{};
  double loop_turn_ = 0;
};

}  // namespace cape

struct Cape {
  static constexpr const char* id = "cape";
  static constexpr const char* name = "Cape on a running character";
  static constexpr const char* version = "1.0.0";
  static constexpr const char* description =
      "Cape attached to the shoulders of a capsule character that walks, turns, runs and stops "
      "on a loop; the cape collides with the body";
  static constexpr auto params = concat(
      cape::grid_params(),
      std::array{
          sdk::real_param("walk.speed", 1.5, 0.01, 20.0, "m/s", "walking speed"),
          sdk::real_param("run.speed", 5.0, 0.01, 20.0, "m/s", "running speed"),
          sdk::real_param("start.duration", 0.5, 0.01, 100.0, "s",
                          "from standing to walking speed"),
          sdk::real_param("walk.duration", 1.5, 0.0, 100.0, "s", "walking straight"),
          sdk::real_param("turn.duration", 1.0, 0.01, 100.0, "s", "turning while walking"),
          sdk::real_param("turn.angle", 90.0, -180.0, 180.0, "deg",
                          "heading change in the turn (positive: to the left)"),
          sdk::real_param("speedup.duration", 1.0, 0.01, 100.0, "s",
                          "from walking to running speed"),
          sdk::real_param("run.duration", 2.0, 0.0, 100.0, "s", "running straight"),
          sdk::real_param("stop.duration", 1.0, 0.01, 100.0, "s", "from running speed to standing"),
          sdk::real_param("rest.duration", 1.0, 0.0, 100.0, "s",
                          "standing before the loop starts again"),
          sdk::real_param("torso.radius", 0.16, 0.01, 1.0, "m",
                          "the torso capsule's radius at the shoulders (0.85 x at the hips)"),
          sdk::real_param("torso.length", 0.45, 0.01, 2.0, "m",
                          "the torso capsule's length, hips to shoulders"),
          sdk::real_param("shoulders.radius", 0.07, 0.01, 1.0, "m",
                          "the shoulder bar capsule's radius"),
          sdk::real_param("shoulders.width", 0.36, 0.01, 2.0, "m",
                          "the shoulder bar's length between its end centres"),
          sdk::real_param("arms.radius", 0.05, 0.01, 1.0, "m", "the upper arm capsules' radius"),
          sdk::real_param("arms.length", 0.28, 0.01, 2.0, "m", "the upper arms' length"),
          sdk::real_param("friction", 0.3, 0.0, 10.0, "",
                          "Coulomb coefficient between the cape and the body"),
          sdk::real_param("thickness", 0.01, 0.0, 0.1, "m",
                          "distance the cape is kept from the body's surface"),
          sdk::real_param("air.density", 1.225, 0.0, 100.0, "kg/m^3",
                          "air for the drag and lift model (sea level); 0 = none"),
          sdk::vec3_param("air.wind", {0.0, 0.0, 0.0}, -1e3, 1e3, "m/s", "the air's velocity"),
          sdk::real_param("air.drag", 1.2, 0.0, 10.0, "", "drag coefficient of a triangle"),
          sdk::real_param("air.lift", 1.0, 0.0, 10.0, "", "lift coefficient of a triangle"),
      });

  explicit Cape(const sdk::Params& values)
      : cloth_(values),
        script_(values),
        back_(values.real("torso.radius") + values.real("thickness") + cape::back_gap) {
    const double friction = values.real("friction"), thickness = values.real("thickness");
    auto capsule = [&](double radius, double end_radius, double length) {
      clothlab_collider collider{};
      collider.struct_size = sizeof collider;
      collider.shape = CLOTHLAB_COLLIDER_CAPSULE;
      collider.radius = radius;
      collider.end_radius = end_radius;
      collider.half_length = 0.5 * length;
      collider.friction = friction;
      collider.thickness = thickness;
      return collider;
    };
    const double torso_radius = values.real("torso.radius"), torso = values.real("torso.length");
    const double shoulders = values.real("shoulders.width"), arm = values.real("arms.length");
    const double s = std::numbers::sqrt2 / 2;
    // Capsules lie along their local x: the torso and the arms stand up (x to y, a quarter
    // turn about z), the shoulder bar lies across (x to z, a quarter turn about -y).
    colliders_ = {
        capsule(0.85 * torso_radius, torso_radius, torso),
        capsule(values.real("shoulders.radius"), values.real("shoulders.radius"), shoulders),
        capsule(values.real("arms.radius"), values.real("arms.radius"), arm),
        capsule(values.real("arms.radius"), values.real("arms.radius"), arm)};
    const double top = cape::shoulder_height;
    local_ = {{{0.0, top - 0.5 * torso, 0.0}, {s, 0.0, 0.0, s}},
              {{0.0, top, 0.0}, {s, 0.0, -s, 0.0}},
              {{0.0, top - 0.5 * arm, 0.5 * shoulders}, {s, 0.0, 0.0, s}},
              {{0.0, top - 0.5 * arm, -0.5 * shoulders}, {s, 0.0, 0.0, s}}};
    if (cloth_.anchored)
      for (uint32_t col = 0; col < cloth_.cols; ++col) attached_.push_back(col);
    air_.struct_size = sizeof air_;
    air_.density = values.real("air.density");
    air_.drag_coefficient = values.real("air.drag");
    air_.lift_coefficient = values.real("air.lift");
    const std::array<double, 3> wind = values.vec3("air.wind");
    for (int axis = 0; axis < 3; ++axis) air_.wind_velocity[axis] = wind[axis];
  }

  void describe(clothlab_scene& scene) const {
    cloth_.fill(scene);
    // The cape as it hangs at t = 0 behind the standing character (heading 0).
    set_vec3(scene.origin, -back_, cape::shoulder_height, -0.5 * cloth_.width);
    set_vec3(scene.col_axis, 0.0, 0.0, 1.0);
    set_vec3(scene.row_axis, 0.0, -1.0, 0.0);
    // Pinned as well as attached: the scene says which particles no force moves.
    scene.pinned_count = static_cast<uint32_t>(attached_.size());
    scene.pinned = attached_.data();
  }

  std::span<const clothlab_collider> colliders() const { return colliders_; }
  clothlab_pose collider_pose(uint32_t index, double t) const {
    const cape::BodyState body = script_.at(t);
    const cape::Vec3 offset = cape::yaw(body.heading, local_[index].centre);
    const std::array<double, 4> heading{std::cos(0.5 * body.heading), 0.0,
                                        std::sin(0.5 * body.heading), 0.0};
    const std::array<double, 4> orientation = cape::multiply(heading, local_[index].orientation);
    return {
        {body.position[0] + offset[0], body.position[1] + offset[1], body.position[2] + offset[2]},
        {orientation[0], orientation[1], orientation[2], orientation[3]}};
  }

  clothlab_air air() const { return air_; }

  std::span<const uint32_t> attached_particles() const { return attached_; }
  // The top edge's points in the body frame, carried along: x = p + R r, v = p' + w y x R r.
  void attachment_targets(double t, std::span<double> positions,
                          std::span<double> velocities) const {
    const cape::BodyState body = script_.at(t);
    const double spacing = cloth_.cols > 1 ? cloth_.width / (cloth_.cols - 1) : 0.0;
    for (std::size_t k = 0; k < attached_.size(); ++k) {
      const cape::Vec3 r = cape::yaw(
          body.heading, {-back_, cape::shoulder_height, -0.5 * cloth_.width + spacing * k});
      const cape::Vec3 spin{body.turn_rate * r[2], 0.0, -body.turn_rate * r[0]};
      for (int axis = 0; axis < 3; ++axis) {
        positions[3 * k + axis] = body.position[axis] + r[axis];
        velocities[3 * k + axis] = body.velocity[axis] + spin[axis];
      }
    }
  }

 private:
  struct LocalPose {
    cape::Vec3 centre;
    std::array<double, 4> orientation;
  };

  GridCloth cloth_;
  cape::Script script_;
  double back_;
  std::vector<clothlab_collider> colliders_;
  std::vector<LocalPose> local_;
  std::vector<uint32_t> attached_;
  clothlab_air air_{};
};

}  // namespace clothlab::builtin

CLOTHLAB_PLUGIN_ENTRY("clothlab-builtin-cape", "1.0.0", clothlab::sdk::integrators<>,
                      clothlab::sdk::scenarios<clothlab::builtin::Cape>)
