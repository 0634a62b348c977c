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
    const double normal_speed = v[0] * n[0] + v[1] * n[1] + v[2] * n[2];
    if (normal_speed >= 0) continue;  // already leaving: no impulse, no friction
    Vec3 tangential{};
    for (int k = 0; k < 3; ++k) tangential[k] = v[k] - normal_speed * n[k];
    const double tangential_speed =
        std::sqrt(tangential[0] * tangential[0] + tangential[1] * tangential[1] +
                  tangential[2] * tangential[2]);
    const double slowed = std::max(0.0, tangential_speed - collider.friction * -normal_speed);
    const double keep = tangential_speed > 0 ? slowed / tangential_speed : 0.0;
    for (int k = 0; k < 3; ++k) v[k] = keep * tangential[k];
  }
  return touched;
}

double penetration_depth(std::span<const Collider> colliders, const Vec3& x) {
  double depth = 0;
  for (const Collider& collider : colliders)
    depth = std::max(depth, -surface_distance(collider, x).distance);
  return depth;
}

}  // namespace clothlab
