// A rigid analytic body the cloth may not enter (clothlab/ext/colliders.h defines the shapes),
// and the signed distance of a point from its surface.
#pragma once

#include <clothlab/ext/colliders.h>

#include <array>
#include <string_view>

namespace clothlab {

using Vec3 = std::array<double, 3>;

enum class ColliderShape { Sphere, Capsule, Plane, Box };

std::string_view to_string(ColliderShape shape);

// Local to world: world = position + R(orientation) local, orientation a unit quaternion
// (w, x, y, z).
struct Pose {
  Vec3 position{0, 0, 0};
  std::array<double, 4> orientation{1, 0, 0, 0};

  Vec3 to_world(const Vec3& local) const;
  Vec3 rotate(const Vec3& local) const;
  Vec3 to_local(const Vec3& world) const;
};

// How a pose changes: a point p of the body moves at velocity + angular_velocity x (p -
// pose.position) (world frame).
struct Motion {
  Vec3 velocity{0, 0, 0};          // m/s
  Vec3 angular_velocity{0, 0, 0};  // rad/s
};

struct Collider {
  ColliderShape shape = ColliderShape::Sphere;
  double radius = 0;           // sphere; capsule at its -x end
  double end_radius = 0;       // capsule at its +x end
  double half_length = 0;      // capsule
  Vec3 half_extents{0, 0, 0};  // box
  double friction = 0;         // Coulomb coefficient
  double thickness = 0;        // particles are kept this far outside the surface
  Pose pose;
  Motion motion;

  // The velocity of the body's point at `point` (world).
  Vec3 velocity_at(const Vec3& point) const;
  // The collider `seconds` later, moved at its velocity (constant over that time).
  Collider advanced(double seconds) const;
};

// Copies and validates a scenario's collider; throws std::invalid_argument naming the field,
// its value and the allowed range ("radius = -1, allowed > 0").
Collider collider_from_abi(const clothlab_collider& collider);
// Copies and validates a pose; throws std::invalid_argument for a non-finite component or an
// orientation that is not a unit quaternion (within 1e-6; the copy is normalised).
Pose pose_from_abi(const clothlab_pose& pose);

// Copies and validates a pose's velocity (clothlab.colliders/2); throws std::invalid_argument
// for a non-finite component ("velocity.x = inf, allowed finite").
Motion motion_from_abi(const clothlab_collider_motion& motion);
// The constant motion that takes `before` to `after` in dt (the shorter way round).
Motion motion_between(const Pose& before, const Pose& after, double dt);
// Throws std::invalid_argument when a scenario's velocity disagrees with the motion its poses
// make (`derived`, motion_between): more than 1 m/s plus half the larger speed apart, or
// 1 rad/s plus half the larger turn rate ("velocity 20 m/s, its poses move at 0 m/s: allowed
// within 11 m/s of them").
void check_motion_agrees(const Motion& given, const Motion& derived);

// A scripted path may move a collider fast, not jump: between two poses dt apart it moves at
// most max_collider_speed and turns at most max_collider_turn_rate (faster than anything a game
// character carries: a thrown ball flies at about 45 m/s, a bat swings at about 50 rad/s).
inline constexpr double max_collider_speed = 100.0;      // m/s
inline constexpr double max_collider_turn_rate = 100.0;  // rad/s
// Throws std::invalid_argument naming what moved too far, how far and the allowed speed
// ("position moved 2 m in 0.0167 s (120 m/s), allowed <= 100 m/s").
void check_pose_continuity(const Pose& before, const Pose& after, double dt);

// How far a point lies outside the surface (negative inside) and the outward unit normal of
// the surface at its closest point (on a shape's medial set, e.g. a sphere's centre, the
// normal of one of the closest points).
struct SurfaceDistance {
  double distance = 0;
  Vec3 normal{0, 1, 0};
};

SurfaceDistance surface_distance(const Collider& collider, const Vec3& point);

}  // namespace clothlab
