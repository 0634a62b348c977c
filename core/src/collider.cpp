// Collider poses (quaternion rotations) and the checks on a scenario's colliders and poses.
#include <algorithm>
#include <clothlab/core/collider.hpp>
#include <cmath>
#include <stdexcept>
#include <string>

#include "value_text.hpp"

namespace clothlab {
namespace {

// Rotates v by the unit quaternion (w, x, y, z), or by its inverse.
Vec3 rotate_by(const std::array<double, 4>& q, const Vec3& v, bool inverse) {
  // Most bodies a cloth meets are never turned (a table, a character's capsules as set up).
  if (q[1] == 0 && q[2] == 0 && q[3] == 0) return v;
  const double w = q[0];
  const double s = inverse ? -1.0 : 1.0;
  const Vec3 u{s * q[1], s * q[2], s * q[3]};
  // v' = v + 2 w (u x v) + 2 u x (u x v)
  const Vec3 uv{u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
  const Vec3 uuv{u[1] * uv[2] - u[2] * uv[1], u[2] * uv[0] - u[0] * uv[2],
                 u[0] * uv[1] - u[1] * uv[0]};
  return {v[0] + 2 * (w * uv[0] + uuv[0]), v[1] + 2 * (w * uv[1] + uuv[1]),
          v[2] + 2 * (w * uv[2] + uuv[2])};
}

using Quaternion = std::array<double, 4>;

Quaternion multiply(const Quaternion& a, const Quaternion& b) {
  return {a[0] * b[0] - a[1] * b[1] - a[2] * b[2] - a[3] * b[3],
          a[0] * b[1] + a[1] * b[0] + a[2] * b[3] - a[3] * b[2],
          a[0] * b[2] - a[1] * b[3] + a[2] * b[0] + a[3] * b[1],
          a[0] * b[3] + a[1] * b[2] - a[2] * b[1] + a[3] * b[0]};
}

double length(const Vec3& v) { return std::hypot(v[0], v[1], v[2]); }

Vec3 difference(const Vec3& a, const Vec3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }

void require(bool ok, const std::string& field, double value, const char* allowed) {
  if (!ok)
    throw std::invalid_argument(field + " = " + detail::value_text(value) + ", allowed " + allowed);
}

void require_positive(const std::string& field, double value) {
  require(std::isfinite(value) && value > 0, field, value, "finite > 0");
}

}  // namespace

std::string_view to_string(ColliderShape shape) {
  switch (shape) {
    case ColliderShape::Sphere:
      return "sphere";
    case ColliderShape::Capsule:
      return "capsule";
    case ColliderShape::Plane:
      return "plane";
    case ColliderShape::Box:
      return "box";
  }
  return "unknown";
}

Vec3 Pose::rotate(const Vec3& local) const { return rotate_by(orientation, local, false); }

Vec3 Pose::to_world(const Vec3& local) const {
  const Vec3 turned = rotate(local);
  return {turned[0] + position[0], turned[1] + position[1], turned[2] + position[2]};
}

Vec3 Pose::to_local(const Vec3& world) const {
  return rotate_by(orientation,
                   {world[0] - position[0], world[1] - position[1], world[2] - position[2]}, true);
}

Vec3 Collider::velocity_at(const Vec3& point) const {
  const Vec3& w = motion.angular_velocity;
  const Vec3 r = difference(point, pose.position);
  const Vec3& v = motion.velocity;
  return {v[0] + w[1] * r[2] - w[2] * r[1], v[1] + w[2] * r[0] - w[0] * r[2],
          v[2] + w[0] * r[1] - w[1] * r[0]};
}

Collider Collider::advanced(double seconds) const {
  Collider out = *this;
  for (int k = 0; k < 3; ++k) out.pose.position[k] += seconds * motion.velocity[k];
  const double rate = length(motion.angular_velocity);
  if (rate > 0) {
    const double half = 0.5 * rate * seconds;
    const double along = std::sin(half) / rate;
    const Quaternion turn{std::cos(half), along * motion.angular_velocity[0],
                          along * motion.angular_velocity[1], along * motion.angular_velocity[2]};
    out.pose.orientation = multiply(turn, pose.orientation);
  }
  return out;
}

Collider collider_from_abi(const clothlab_collider& in) {
  if (in.struct_size < sizeof(clothlab_collider))
    throw std::invalid_argument("collider struct_size = " + std::to_string(in.struct_size) +
                                ", allowed at least " + std::to_string(sizeof(clothlab_collider)));
  Collider out;
  switch (in.shape) {
    case CLOTHLAB_COLLIDER_SPHERE:
      out.shape = ColliderShape::Sphere;
      require_positive("radius", in.radius);
      break;
    case CLOTHLAB_COLLIDER_CAPSULE:
      out.shape = ColliderShape::Capsule;
      require_positive("radius", in.radius);
      require_positive("end_radius", in.end_radius);
      require_positive("half_length", in.half_length);
      break;
    case CLOTHLAB_COLLIDER_PLANE:
      out.shape = ColliderShape::Plane;
      break;
    case CLOTHLAB_COLLIDER_BOX:
      out.shape = ColliderShape::Box;
      for (int k = 0; k < 3; ++k)
        require_positive("half_extents[" + std::to_string(k) + "]", in.half_extents[k]);
      break;
    default:
      throw std::invalid_argument("shape = " + std::to_string(in.shape) +
                                  ", allowed 1 (sphere), 2 (capsule), 3 (plane) or 4 (box)");
  }
  require(std::isfinite(in.friction) && in.friction >= 0, "friction", in.friction, "finite >= 0");
  require(std::isfinite(in.thickness) && in.thickness >= 0, "thickness", in.thickness,
          "finite >= 0");
  out.radius = in.radius;
  out.end_radius = in.end_radius;
  out.half_length = in.half_length;
  for (int k = 0; k < 3; ++k) out.half_extents[k] = in.half_extents[k];
  out.friction = in.friction;
  out.thickness = in.thickness;
  return out;
}

Pose pose_from_abi(const clothlab_pose& in) {
  static constexpr const char* axes[] = {"x", "y", "z"};
  static constexpr const char* parts[] = {"w", "x", "y", "z"};
  Pose out;
  for (int k = 0; k < 3; ++k) {
    require(std::isfinite(in.position[k]), std::string("position.") + axes[k], in.position[k],
            "finite");
    out.position[k] = in.position[k];
  }
  double squared = 0;
  for (int k = 0; k < 4; ++k) {
    require(std::isfinite(in.orientation[k]), std::string("orientation.") + parts[k],
            in.orientation[k], "finite");
    squared += in.orientation[k] * in.orientation[k];
  }
  const double length = std::sqrt(squared);
  require(std::abs(length - 1) <= 1e-6, "|orientation|", length, "1 (a unit quaternion, 1e-6)");
  for (int k = 0; k < 4; ++k) out.orientation[k] = in.orientation[k] / length;
  return out;
}

Motion motion_from_abi(const clothlab_collider_motion& in) {
  static constexpr const char* axes[] = {"x", "y", "z"};
  Motion out;
  for (int k = 0; k < 3; ++k) {
    require(std::isfinite(in.velocity[k]), std::string("velocity.") + axes[k], in.velocity[k],
            "finite");
    require(std::isfinite(in.angular_velocity[k]), std::string("angular_velocity.") + axes[k],
            in.angular_velocity[k], "finite");
    out.velocity[k] = in.velocity[k];
    out.angular_velocity[k] = in.angular_velocity[k];
  }
  return out;
}

Motion motion_between(const Pose& before, const Pose& after, double dt) {
  Motion out;
  for (int k = 0; k < 3; ++k) out.velocity[k] = (after.position[k] - before.position[k]) / dt;
  const Quaternion& q = before.orientation;
  Quaternion turn = multiply(after.orientation, {q[0], -q[1], -q[2], -q[3]});
  if (turn[0] < 0)
    for (double& part : turn) part = -part;  // the same rotation, the shorter way round
  const double sine = std::hypot(turn[1], turn[2], turn[3]);
  if (sine > 0) {
    const double rate = 2 * std::atan2(sine, turn[0]) / dt;
    for (int k = 0; k < 3; ++k) out.angular_velocity[k] = rate * turn[k + 1] / sine;
  }
  return out;
}

void check_motion_agrees(const Motion& given, const Motion& derived) {
  const auto check = [](const char* name, const Vec3& a, const Vec3& b, const char* unit) {
    const double apart = length(difference(a, b));
    const double allowed = 1.0 + 0.5 * std::max(length(a), length(b));
    if (!(apart <= allowed))
      throw std::invalid_argument(std::string(name) + " " + detail::value_text(length(a)) + " " +
                                  unit + ", its poses move at " + detail::value_text(length(b)) +
                                  " " + unit + " (" + detail::value_text(apart) +
                                  " apart): allowed within " + detail::value_text(allowed) + " " +
                                  unit + " of them");
  };
  check("velocity", given.velocity, derived.velocity, "m/s");
  check("angular_velocity", given.angular_velocity, derived.angular_velocity, "rad/s");
}

void check_pose_continuity(const Pose& before, const Pose& after, double dt) {
  const Vec3& p = before.position;
  const Vec3& q = after.position;
  const double moved = std::hypot(q[0] - p[0], q[1] - p[1], q[2] - p[2]);
  if (!(moved <= max_collider_speed * dt))
    throw std::invalid_argument("position moved " + detail::value_text(moved) + " m in " +
                                detail::value_text(dt) + " s (" + detail::value_text(moved / dt) +
                                " m/s), allowed <= " + detail::value_text(max_collider_speed) +
                                " m/s");
  double cosine = 0;
  for (int k = 0; k < 4; ++k) cosine += before.orientation[k] * after.orientation[k];
  // The rotation between two unit quaternions turns by 2 acos |<a, b>|.
  const double turned = 2 * std::acos(std::min(1.0, std::abs(cosine)));
  if (!(turned <= max_collider_turn_rate * dt))
    throw std::invalid_argument(
        "orientation turned " + detail::value_text(turned) + " rad in " + detail::value_text(dt) +
        " s (" + detail::value_text(turned / dt) +
        " rad/s), allowed <= " + detail::value_text(max_collider_turn_rate) + " rad/s");
}

}  // namespace clothlab
