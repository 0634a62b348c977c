#include <algorithm>
#include <clothlab/core/contact.hpp>
#include <cmath>

namespace clothlab {

bool resolve_contact(std::span<const Collider> colliders, Vec3& x, Vec3& v) {
  bool touched = false;
  for (const Collider& collider : colliders) {
    const SurfaceDistance surface = surface_distance(collider, x);
    if (surface.distance >= collider.thickness) continue;
    touched = true;
    const Vec3& n = surface.normal;
    const double push = collider.thickness - surface.distance;
    for (int k = 0; k < 3; ++k) x[k] += push * n[k];
    // The response acts on the velocity relative to the body's surface there.
    const Vec3 body = collider.velocity_at(x);
    Vec3 relative{};
    for (int k = 0; k < 3; ++k) relative[k] = v[k] - body[k];
    const double normal_speed = relative[0] * n[0] + relative[1] * n[1] + relative[2] * n[2];
    if (normal_speed >= 0) continue;  // already leaving: no impulse, no friction
    Vec3 tangential{};
    for (int k = 0; k < 3; ++k) tangential[k] = relative[k] - normal_speed * n[k];
    const double tangential_speed =
        std::sqrt(tangential[0] * tangential[0] + tangential[1] * tangential[1] +
                  tangential[2] * tangential[2]);
    const double slowed = std::max(0.0, tangential_speed - collider.friction * -normal_speed);
    const double keep = tangential_speed > 0 ? slowed / tangential_speed : 0.0;
    for (int k = 0; k < 3; ++k) v[k] = body[k] + keep * tangential[k];
  }
  return touched;
}

namespace {

double dot(const Vec3& a, const Vec3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

constexpr int kAdvances = 256;

// Where on the path from `from` to `to` (0 .. 1) it first comes within the collider's thickness;
// nullopt-like -1 when it never does.
double first_entry(const Collider& collider, const Vec3& from, const Vec3& to) {
  const Vec3 path{to[0] - from[0], to[1] - from[1], to[2] - from[2]};
  const double length = std::sqrt(dot(path, path));
  if (length == 0) return -1;
  double s = 0;
  for (int advance = 0; advance < kAdvances && s <= 1; ++advance) {
    const Vec3 at{from[0] + s * path[0], from[1] + s * path[1], from[2] + s * path[2]};
    const double clearance = surface_distance(collider, at).distance - collider.thickness;
    if (clearance < 0) return s;
    s += std::max(clearance, length / kAdvances) / length;
  }
  return -1;
}

// The particle's start where the body is now: the same point of the body's frame. A body that
// has not turned (most: a table, a character's translation) only carries it along.
Vec3 start_on_body(const Collider& before, const Collider& now, const Vec3& from) {
  if (before.pose.orientation == now.pose.orientation)
    return {from[0] + (now.pose.position[0] - before.pose.position[0]),
            from[1] + (now.pose.position[1] - before.pose.position[1]),
            from[2] + (now.pose.position[2] - before.pose.position[2])};
  return now.pose.to_world(before.pose.to_local(from));
}

// Where on the path from `from` to `to` (both where the body is now) the particle entered the
// collider's thickness, when the path passed through the collider or past its middle; -1 when
// it did not.
double crossing(const Collider& collider, const Vec3& from, const Vec3& to) {
  const Vec3 path{to[0] - from[0], to[1] - from[1], to[2] - from[2]};
  const double half = 0.5 * std::sqrt(dot(path, path));
  const Vec3 middle{from[0] + 0.5 * path[0], from[1] + 0.5 * path[1], from[2] + 0.5 * path[2]};
  // The path lies within `half` of its middle: farther than that from the surface, it never
  // enters the collider, so it can neither pass through it nor past its middle (the common
  // case, one distance per particle, also for one resting in the thickness band).
  if (surface_distance(collider, middle).distance > half) return -1;
  if (dot(surface_distance(collider, from).normal, surface_distance(collider, to).normal) >= 0)
    return -1;  // the same side: the end's own resolution is right
  return first_entry(collider, from, to);
}

}  // namespace

bool resolve_swept_contact(std::span<const Collider> before, std::span<const Collider> now,
                           const Vec3& from, Vec3& x, Vec3& v) {
  bool rewound = false;
  for (std::size_t k = 0; k < now.size(); ++k) {
    const Vec3 start = start_on_body(before[k], now[k], from);
    const double s = crossing(now[k], start, x);
    if (s < 0) continue;
    for (int axis = 0; axis < 3; ++axis) x[axis] = start[axis] + s * (x[axis] - start[axis]);
    rewound = true;
  }
  return resolve_contact(now, x, v) || rewound;
}

bool crossed_a_collider(std::span<const Collider> before, std::span<const Collider> now,
                        const Vec3& from, const Vec3& to) {
  for (std::size_t k = 0; k < now.size(); ++k)
    if (crossing(now[k], start_on_body(before[k], now[k], from), to) >= 0) return true;
  return false;
}

ContactDepths contact_depths(std::span<const Collider> colliders, const Vec3& x) {
  ContactDepths depths;
  for (const Collider& collider : colliders) {
    const double inside = -surface_distance(collider, x).distance;
    depths.penetration = std::max(depths.penetration, inside);
    depths.past_thickness = std::max(depths.past_thickness, inside - collider.thickness);
  }
  return depths;
}

double penetration_depth(std::span<const Collider> colliders, const Vec3& x) {
  return contact_depths(colliders, x).penetration;
}

double depth_past_thickness(std::span<const Collider> colliders, const Vec3& x) {
  return contact_depths(colliders, x).past_thickness;
}

}  // namespace clothlab
