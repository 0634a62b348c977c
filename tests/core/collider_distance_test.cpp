// Collider geometry: signed distances and normals of each shape against hand-computed values,
// the tapered capsule against an independent definition (the union of the spheres swept along
// its axis, minimised by brute force), every normal against the distance's finite-difference
// gradient, and the checks on a scenario's colliders and poses.
#include <gtest/gtest.h>

#include <algorithm>
#include <clothlab/core/collider.hpp>
#include <cmath>
#include <random>
#include <stdexcept>
#include <string>

namespace clothlab {
namespace {

constexpr double pi = 3.14159265358979323846;

// A rotation by `angle` about a unit axis.
std::array<double, 4> about(const Vec3& axis, double angle) {
  const double s = std::sin(angle / 2);
  return {std::cos(angle / 2), s * axis[0], s * axis[1], s * axis[2]};
}

void expect_near(const Vec3& actual, const Vec3& expected, double tolerance) {
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(actual[k], expected[k], tolerance) << "component " << k;
}

Collider sphere(double radius, Vec3 centre) {
  Collider c;
  c.shape = ColliderShape::Sphere;
  c.radius = radius;
  c.pose.position = centre;
  return c;
}

Collider capsule(double radius, double end_radius, double half_length, Pose pose = {}) {
  Collider c;
  c.shape = ColliderShape::Capsule;
  c.radius = radius;
  c.end_radius = end_radius;
  c.half_length = half_length;
  c.pose = pose;
  return c;
}

TEST(ColliderDistance, SphereOutsideInsideAndAtItsCentre) {
  const Collider c = sphere(0.5, {1, 2, 3});
  SurfaceDistance d = surface_distance(c, {1, 2, 4});
  EXPECT_NEAR(d.distance, 0.5, 1e-15);
  expect_near(d.normal, {0, 0, 1}, 1e-15);
  d = surface_distance(c, {1, 1.9, 3});
  EXPECT_NEAR(d.distance, -0.4, 1e-15);
  expect_near(d.normal, {0, -1, 0}, 1e-15);
  EXPECT_NEAR(surface_distance(c, {1, 2, 3}).distance, -0.5, 1e-15);
}

TEST(ColliderDistance, CapsuleSideAndEndsWhenTurnedUpright) {
  // Its axis turned from x to y: the ends' centres at y = -1 and y = +1.
  Pose upright;
  upright.orientation = about({0, 0, 1}, pi / 2);
  const Collider c = capsule(0.2, 0.2, 1.0, upright);
  SurfaceDistance d = surface_distance(c, {0.5, 0.3, 0});
  EXPECT_NEAR(d.distance, 0.3, 1e-12);
  expect_near(d.normal, {1, 0, 0}, 1e-12);
  d = surface_distance(c, {0, 1.5, 0});
  EXPECT_NEAR(d.distance, 0.3, 1e-12);
  expect_near(d.normal, {0, 1, 0}, 1e-12);
  d = surface_distance(c, {0, -1.1, 0.1});
  EXPECT_NEAR(d.distance, std::sqrt(0.02) - 0.2, 1e-12);
}

// The round cone is the union of the spheres centred on its axis at s in [-L/2, L/2] with
// radii going linearly from r_a to r_b: its signed distance outside is min_s |p - c(s)| - r(s).
double swept_spheres_distance(const Collider& c, const Vec3& p) {
  double best = 1e300;
  constexpr int samples = 200000;
  for (int i = 0; i <= samples; ++i) {
    const double f = static_cast<double>(i) / samples;
    const double s = -c.half_length + 2 * c.half_length * f;
    const double r = c.radius + (c.end_radius - c.radius) * f;
    best = std::min(best, std::hypot(p[0] - s, p[1], p[2]) - r);
  }
  return best;
}

TEST(ColliderDistance, TaperedCapsuleMatchesTheUnionOfSweptSpheres) {
  std::mt19937 random(7);
  std::uniform_real_distribution<double> coordinate(-2.0, 2.0);
  for (const auto& [r_a, r_b] : {std::pair{0.3, 0.1}, std::pair{0.1, 0.45}, std::pair{0.2, 0.2}}) {
    const Collider c = capsule(r_a, r_b, 0.8);
    int outside = 0;
    for (int trial = 0; trial < 200; ++trial) {
      const Vec3 p{coordinate(random), coordinate(random), coordinate(random)};
      const double expected = swept_spheres_distance(c, p);
      if (expected <= 0) continue;  // inside, the union's min is no distance
      ++outside;
      EXPECT_NEAR(surface_distance(c, p).distance, expected, 1e-6)
          << r_a << " " << r_b << " at " << p[0] << " " << p[1] << " " << p[2];
    }
    EXPECT_GT(outside, 100);
  }
}

TEST(ColliderDistance, OneEndSwallowingTheOtherIsThatSphere) {
  const Collider c = capsule(1.0, 0.1, 0.2);  // |r_a - r_b| = 0.9 >= L = 0.4
  EXPECT_NEAR(surface_distance(c, {-0.2, 2.0, 0}).distance, 1.0, 1e-12);
}

TEST(ColliderDistance, PlaneTurnedToFaceZ) {
  Collider c;
  c.shape = ColliderShape::Plane;
  c.pose.position = {0, 0, 0.5};
  c.pose.orientation = about({1, 0, 0}, pi / 2);  // local +y to world +z
  const SurfaceDistance d = surface_distance(c, {3, -4, 1.2});
  EXPECT_NEAR(d.distance, 0.7, 1e-12);
  expect_near(d.normal, {0, 0, 1}, 1e-12);
  EXPECT_NEAR(surface_distance(c, {0, 0, 0}).distance, -0.5, 1e-12);
}

TEST(ColliderDistance, BoxFacesEdgesAndInside) {
  Collider c;
  c.shape = ColliderShape::Box;
  c.half_extents = {1, 2, 3};
  SurfaceDistance d = surface_distance(c, {2, 0, 0});
  EXPECT_NEAR(d.distance, 1, 1e-15);
  expect_near(d.normal, {1, 0, 0}, 1e-15);
  d = surface_distance(c, {-2, -3, 0});
  EXPECT_NEAR(d.distance, std::sqrt(2.0), 1e-15);
  expect_near(d.normal, {-std::sqrt(0.5), -std::sqrt(0.5), 0}, 1e-15);
  d = surface_distance(c, {0.9, 0.5, -2.5});
  EXPECT_NEAR(d.distance, -0.1, 1e-15);
  expect_near(d.normal, {1, 0, 0}, 1e-15);
}

TEST(ColliderDistance, NormalsAreTheDistancesGradient) {
  Pose tilted;
  tilted.position = {0.3, -0.2, 0.1};
  tilted.orientation = about({0.6, 0.0, 0.8}, 0.7);
  Collider box;
  box.shape = ColliderShape::Box;
  box.half_extents = {0.4, 0.3, 0.5};
  box.pose = tilted;
  Collider plane;
  plane.shape = ColliderShape::Plane;
  plane.pose = tilted;
  const Collider ball = sphere(0.6, tilted.position);
  const Collider cone = capsule(0.4, 0.15, 0.6, tilted);
  std::mt19937 random(11);
  std::uniform_real_distribution<double> coordinate(-1.5, 1.5);
  constexpr double h = 1e-6;
  for (const Collider* c : std::array<const Collider*, 4>{&box, &plane, &ball, &cone}) {
    for (int trial = 0; trial < 100; ++trial) {
      const Vec3 p{coordinate(random), coordinate(random), coordinate(random)};
      const SurfaceDistance d = surface_distance(*c, p);
      if (d.distance < 0.05) continue;  // outside: the distance is smooth there
      Vec3 gradient{};
      for (int k = 0; k < 3; ++k) {
        Vec3 plus = p, minus = p;
        plus[k] += h;
        minus[k] -= h;
        gradient[k] =
            (surface_distance(*c, plus).distance - surface_distance(*c, minus).distance) / (2 * h);
      }
      expect_near(d.normal, gradient, 1e-6);
    }
  }
}

std::string refusal(const clothlab_collider& raw) {
  try {
    (void)collider_from_abi(raw);
  } catch (const std::invalid_argument& error) {
    return error.what();
  }
  return "";
}

clothlab_collider raw_capsule() {
  clothlab_collider raw{};
  raw.struct_size = sizeof raw;
  raw.shape = CLOTHLAB_COLLIDER_CAPSULE;
  raw.radius = 0.1;
  raw.end_radius = 0.1;
  raw.half_length = 0.3;
  raw.friction = 0.5;
  raw.thickness = 0.01;
  return raw;
}

TEST(ColliderChecks, MalformedShapesNameTheFieldValueAndRange) {
  EXPECT_EQ(refusal(raw_capsule()), "");
  clothlab_collider raw = raw_capsule();
  raw.radius = -1;
  EXPECT_EQ(refusal(raw), "radius = -1, allowed finite > 0");
  raw = raw_capsule();
  raw.half_length = 0;
  EXPECT_EQ(refusal(raw), "half_length = 0, allowed finite > 0");
  raw = raw_capsule();
  raw.friction = -0.25;
  EXPECT_EQ(refusal(raw), "friction = -0.25, allowed finite >= 0");
  raw = raw_capsule();
  raw.thickness = std::nan("");
  EXPECT_EQ(refusal(raw), "thickness = nan, allowed finite >= 0");
  raw = raw_capsule();
  raw.shape = 9;
  EXPECT_EQ(refusal(raw), "shape = 9, allowed 1 (sphere), 2 (capsule), 3 (plane) or 4 (box)");
  raw = raw_capsule();
  raw.shape = CLOTHLAB_COLLIDER_BOX;
  raw.half_extents[0] = raw.half_extents[1] = 1;
  EXPECT_EQ(refusal(raw), "half_extents[2] = 0, allowed finite > 0");
}

TEST(ColliderChecks, PosesMustBeFiniteWithAUnitQuaternion) {
  clothlab_pose raw{{0, 1, 2}, {1, 0, 0, 0}};
  EXPECT_EQ(pose_from_abi(raw).position[2], 2);
  raw.position[1] = INFINITY;
  EXPECT_THROW(
      {
        try {
          (void)pose_from_abi(raw);
        } catch (const std::invalid_argument& error) {
          EXPECT_STREQ(error.what(), "position.y = inf, allowed finite");
          throw;
        }
      },
      std::invalid_argument);
  raw = {{0, 0, 0}, {2, 0, 0, 0}};
  try {
    (void)pose_from_abi(raw);
    FAIL() << "a quaternion of length 2 was accepted";
  } catch (const std::invalid_argument& error) {
    EXPECT_STREQ(error.what(), "|orientation| = 2, allowed 1 (a unit quaternion, 1e-6)");
  }
}

}  // namespace
}  // namespace clothlab
