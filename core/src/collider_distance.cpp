// Signed distance and outward normal of each collider shape, computed in the collider's frame.
#include <algorithm>
#include <clothlab/core/collider.hpp>
#include <cmath>

namespace clothlab {
namespace {

double dot(const Vec3& a, const Vec3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
double norm(const Vec3& a) { return std::sqrt(dot(a, a)); }

// From a centre: the distance beyond `radius` and the direction away from the centre (+y at
// the centre itself, where every direction is as close).
SurfaceDistance from_centre(const Vec3& offset, double radius) {
  const double length = norm(offset);
  if (length == 0) return {-radius, {0, 1, 0}};
  return {length - radius, {offset[0] / length, offset[1] / length, offset[2] / length}};
}

SurfaceDistance sphere(const Collider& c, const Vec3& p) { return from_centre(p, c.radius); }

// A round cone: the segment a = (-L/2, 0, 0) to b = (L/2, 0, 0) swept by a sphere of radius r_a
// at a and r_b at b. In the plane of the axis and the point (u along the axis from a, w away
// from it) the side is the common tangent of the end circles, touching them where the unit
// normal n = (sin phi, cos phi), sin phi = (r_a - r_b) / L, meets them. A point projecting
// (along the side's direction d = (cos phi, -sin phi)) before a's tangent point is closest to
// a's sphere, after b's (at L cos phi along d) to b's sphere, else to the side.
SurfaceDistance capsule(const Collider& c, const Vec3& p) {
  const double length = 2 * c.half_length;
  const double r_a = c.radius, r_b = c.end_radius;
  const Vec3 a{-c.half_length, 0, 0}, b{c.half_length, 0, 0};
  // One end's sphere holds the other: the capsule is that sphere.
  if (std::abs(r_a - r_b) >= length)
    return r_a >= r_b ? from_centre({p[0] - a[0], p[1], p[2]}, r_a)
                      : from_centre({p[0] - b[0], p[1], p[2]}, r_b);
  const double u = p[0] - a[0];
  const double w = std::hypot(p[1], p[2]);
  const double sin_phi = (r_a - r_b) / length;
  const double cos_phi = std::sqrt(1 - sin_phi * sin_phi);
  const double along = u * cos_phi - w * sin_phi;
  if (along <= 0) return from_centre({p[0] - a[0], p[1], p[2]}, r_a);
  if (along >= length * cos_phi) return from_centre({p[0] - b[0], p[1], p[2]}, r_b);
  // Radial direction in 3D; on the axis any perpendicular is as close.
  const Vec3 radial = w > 0 ? Vec3{0, p[1] / w, p[2] / w} : Vec3{0, 1, 0};
  return {u * sin_phi + w * cos_phi - r_a, {sin_phi, cos_phi * radial[1], cos_phi * radial[2]}};
}

SurfaceDistance plane(const Vec3& p) { return {p[1], {0, 1, 0}}; }

// Outside: the distance to the nearest point of the box; inside: minus the distance to the
// nearest face, whose normal is the face's.
SurfaceDistance box(const Collider& c, const Vec3& p) {
  Vec3 beyond{}, q{};
  for (int k = 0; k < 3; ++k) {
    q[k] = std::abs(p[k]) - c.half_extents[k];
    beyond[k] = std::max(q[k], 0.0);
  }
  const double outside = norm(beyond);
  if (outside > 0) {
    Vec3 normal{};
    for (int k = 0; k < 3; ++k) normal[k] = std::copysign(beyond[k] / outside, p[k]);
    return {outside, normal};
  }
  int face = 0;
  for (int k = 1; k < 3; ++k)
    if (q[k] > q[face]) face = k;
  Vec3 normal{0, 0, 0};
  normal[face] = std::copysign(1.0, p[face]);
  return {q[face], normal};
}

}  // namespace

SurfaceDistance surface_distance(const Collider& collider, const Vec3& point) {
  const Vec3 local = collider.pose.to_local(point);
  SurfaceDistance result;
  switch (collider.shape) {
    case ColliderShape::Sphere:
      result = sphere(collider, local);
      break;
    case ColliderShape::Capsule:
      result = capsule(collider, local);
      break;
    case ColliderShape::Plane:
      result = plane(local);
      break;
    case ColliderShape::Box:
      result = box(collider, local);
      break;
  }
  result.normal = collider.pose.rotate(result.normal);
  return result;
}

}  // namespace clothlab
