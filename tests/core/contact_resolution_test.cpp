// Contact resolution against analytic cases: a particle dropped on a plane or a sphere comes to
// rest at the thickness, one sliding on a plane stops where Coulomb's law puts it (v0^2 / 2 mu g),
// a frictionless one keeps its speed, and a fast one whose path is resolved does not tunnel.
// Stepped here by an independent loop (symplectic Euler on one particle), then through the engine's
// clothlab.contacts/1 in both precisions.
#include <clothlab/ext/contacts.h>
#include <gtest/gtest.h>

#include <clothlab/core/cloth.hpp>
#include <clothlab/core/contact.hpp>
#include <cmath>
#include <vector>

#include "cloth_test_support.hpp"

namespace clothlab {
namespace {

constexpr double g = 9.81;

Collider ground(double friction, double thickness) {
  Collider c;
  c.shape = ColliderShape::Plane;
  c.friction = friction;
  c.thickness = thickness;
  return c;
}

struct Particle {
  Vec3 x, v;
};

enum class Resolution { AtTheEnd, Swept };

// Symplectic Euler under gravity, each step followed by the contact resolution: of where the
// step ends, or of the path the step took.
Particle fall(Particle p, std::span<const Collider> colliders, double h, int steps,
              Resolution resolution = Resolution::AtTheEnd) {
  for (int i = 0; i < steps; ++i) {
    const Vec3 from = p.x;
    p.v[1] -= g * h;
    for (int k = 0; k < 3; ++k) p.x[k] += h * p.v[k];
    if (resolution == Resolution::Swept)
      resolve_swept_contact(colliders, from, p.x, p.v);
    else
      resolve_contact(colliders, p.x, p.v);
  }
  return p;
}

Collider thin_capsule() {
  Collider arm;
  arm.shape = ColliderShape::Capsule;
  arm.radius = 0.012;
  arm.end_radius = 0.008;  // tapered
  arm.half_length = 0.4;
  arm.thickness = 0.002;
  arm.friction = 0.3;
  arm.pose.orientation = {std::cos(0.2), 0, std::sin(0.2), 0};  // turned about y
  return arm;
}

TEST(ContactResolution, ADroppedParticleRestsOnAPlaneAtTheThickness) {
  const Collider floor = ground(0.5, 0.01);
  const Particle end = fall({{0.2, 1.0, -0.3}, {0, 0, 0}}, {&floor, 1}, 1e-3, 2000);
  EXPECT_NEAR(end.x[1], 0.01, 1e-12);
  EXPECT_NEAR(end.x[0], 0.2, 1e-12);
  EXPECT_NEAR(end.v[1], 0.0, 1e-12);
  EXPECT_EQ(penetration_depth({&floor, 1}, end.x), 0.0);
}

TEST(ContactResolution, ADroppedParticleRestsOnASphereTopAtRadiusPlusThickness) {
  Collider ball;
  ball.shape = ColliderShape::Sphere;
  ball.radius = 0.3;
  ball.thickness = 0.02;
  ball.friction = 1.0;
  ball.pose.position = {0, 0.5, 0};
  const Particle end = fall({{0, 2.0, 0}, {0, 0, 0}}, {&ball, 1}, 1e-3, 3000);
  EXPECT_NEAR(end.x[1], 0.5 + 0.3 + 0.02, 1e-12);
  EXPECT_NEAR(std::hypot(end.v[0], end.v[1], end.v[2]), 0.0, 1e-12);
}

// Under Coulomb friction a particle sliding at v0 decelerates by mu g and stops after
// v0^2 / (2 mu g); the step's discretisation adds O(v0 h).
TEST(ContactResolution, FrictionStopsASlidingParticleAtTheCoulombDistance) {
  for (const double mu : {0.2, 0.5, 1.0}) {
    const Collider floor = ground(mu, 0.0);
    const double v0 = 2.0, h = 1e-4;
    const Particle end = fall({{0, 0, 0}, {v0, 0, 0}}, {&floor, 1}, h, 40000);
    EXPECT_EQ(end.v[0], 0.0) << mu;
    EXPECT_NEAR(end.x[0], v0 * v0 / (2 * mu * g), 2 * v0 * h) << mu;
    EXPECT_NEAR(end.x[1], 0.0, 1e-12) << mu;
  }
}

TEST(ContactResolution, WithoutFrictionTheTangentialVelocityStays) {
  const Collider floor = ground(0.0, 0.0);
  const Particle end = fall({{0, 0, 0}, {1.5, 0, -0.5}}, {&floor, 1}, 1e-3, 1000);
  EXPECT_NEAR(end.v[0], 1.5, 1e-15);
  EXPECT_NEAR(end.v[2], -0.5, 1e-15);
  EXPECT_NEAR(end.x[0], 1.5, 1e-9);
}

// At 20 m/s and 60 Hz a particle moves 33 cm per step: resolving where the step ends lets it
// through a 2.4 cm arm; resolving its path puts it on top, where it started, and it stays.
TEST(ContactResolution, AFastParticleDoesNotTunnelThroughAThinCapsuleWhenItsPathIsResolved) {
  const Collider arm = thin_capsule();
  const Particle start{{0, 0.05, 0}, {0, -20, 0}};
  const Particle through = fall(start, {&arm, 1}, 1.0 / 60, 3, Resolution::AtTheEnd);
  EXPECT_LT(through.x[1], -0.5);
  const Particle stopped = fall(start, {&arm, 1}, 1.0 / 60, 30, Resolution::Swept);
  EXPECT_NEAR(surface_distance(arm, stopped.x).distance, arm.thickness, 1e-9);
  EXPECT_GT(stopped.x[1], 0.0);
  EXPECT_EQ(penetration_depth({&arm, 1}, stopped.x), 0.0);
}

// Where a step's path crosses no collider's middle, the swept resolution is the end's: a particle
// sliding off a sphere, and one passing beside the arm, end exactly where they did.
TEST(ContactResolution, SweptResolutionChangesNothingForPathsThatDoNotCrossACollider) {
  Collider ball;
  ball.shape = ColliderShape::Sphere;
  ball.radius = 0.3;
  ball.thickness = 0.01;
  ball.friction = 0.2;
  const Particle sliding{{0.05, 0.31, 0.0}, {0.5, 0, 0.2}};
  const Particle a = fall(sliding, {&ball, 1}, 1e-3, 2000, Resolution::AtTheEnd);
  const Particle b = fall(sliding, {&ball, 1}, 1e-3, 2000, Resolution::Swept);
  EXPECT_EQ(a.x, b.x);
  EXPECT_EQ(a.v, b.v);
  const Collider arm = thin_capsule();
  const Particle beside{{0, 0.05, 0.3}, {0, -20, 0}};
  EXPECT_EQ(fall(beside, {&arm, 1}, 1.0 / 60, 3, Resolution::Swept).x,
            fall(beside, {&arm, 1}, 1.0 / 60, 3, Resolution::AtTheEnd).x);
}

TEST(ContactResolution, AParticleLeavingTheSurfaceKeepsItsVelocity) {
  const Collider floor = ground(1.0, 0.1);
  Vec3 x{0, 0.05, 0}, v{3, 1, 0};
  EXPECT_TRUE(resolve_contact({&floor, 1}, x, v));
  EXPECT_NEAR(x[1], 0.1, 1e-15);
  EXPECT_EQ(v, (Vec3{3, 1, 0}));
}

// The engine's clothlab.contacts/1 on a single free particle, stepped by the system's own
// callbacks: the same rest height in float64 and float32, and the host's counts of it.
TEST(ContactResolution, TheEnginesContactsExtensionKeepsTheClothOnTheFloor) {
  for (const Precision precision : {Precision::Float64, Precision::Float32}) {
    Scene scene = testing::bare_scene(1, 1);
    scene.gravity = {0, -g, 0};
    scene.origin = {0, 0.5, 0};
    Cloth cloth(scene, precision, PipelineOptions{});
    const Collider floor = ground(0.5, 0.01);
    cloth.set_colliders({&floor, 1});
    const clothlab_system& system = cloth.system();
    const auto* contacts = static_cast<const clothlab_contacts_extension*>(
        clothlab_system_extension(&system, CLOTHLAB_EXT_CONTACTS));
    ASSERT_NE(contacts, nullptr);
    void* a = system.alloc_vector(system.context);
    for (int step = 0; step < 1000; ++step) {
      ASSERT_EQ(system.eval_acceleration(system.context, 0, system.x, system.v, a), CLOTHLAB_OK);
      system.axpy(system.context, system.v, 1e-3, a);
      system.axpy(system.context, system.x, 1e-3, system.v);
      ASSERT_EQ(contacts->resolve(system.context, 0, system.x, system.v), CLOTHLAB_OK);
    }
    std::vector<double> x;
    cloth.positions(x);
    EXPECT_NEAR(x[1], 0.01, precision == Precision::Float64 ? 1e-12 : 1e-7);
    EXPECT_EQ(cloth.contacts().particles_inside, 0u);
    EXPECT_EQ(cloth.contacts().max_penetration, 0.0);
    // Sunk below the floor by hand: counted, and as deep as it was put.
    cloth.set_state({0, -0.25, 0}, {0, 0, 0});
    EXPECT_EQ(cloth.contacts().particles_inside, 1u);
    EXPECT_NEAR(cloth.contacts().max_penetration, 0.25, 1e-7);
  }
}

// Each particle's depth past the thickness is against the collider it lies in: 0.015 m inside a
// floor 0.02 m thick is within its band, though deeper than the thinner ball's 0.005 m; 0.01 m
// inside the ball is 0.005 m past its thickness.
TEST(ContactResolution, TheDepthPastTheThicknessIsEachCollidersOwn) {
  const Collider floor = ground(0.5, 0.02);
  Collider ball;
  ball.shape = ColliderShape::Sphere;
  ball.pose.position = {5, 0, 0};
  ball.radius = 0.1;
  ball.thickness = 0.005;
  const Collider both[] = {floor, ball};
  EXPECT_NEAR(penetration_depth(both, {0, -0.015, 0}), 0.015, 1e-15);
  EXPECT_EQ(depth_past_thickness(both, {0, -0.015, 0}), 0.0);
  EXPECT_NEAR(depth_past_thickness(both, {5, 0.09, 0}), 0.005, 1e-15);
  EXPECT_EQ(depth_past_thickness(both, {0, 1, 0}), 0.0);  // outside both

  Scene scene = testing::bare_scene(1, 1);
  Cloth cloth(scene, Precision::Float64, PipelineOptions{});
  cloth.set_colliders(both);
  cloth.set_state({0, -0.015, 0}, {0, 0, 0});
  EXPECT_NEAR(cloth.contacts().max_penetration, 0.015, 1e-15);
  EXPECT_EQ(cloth.contacts().max_depth_past_thickness, 0.0);
  cloth.set_state({5, 0.09, 0}, {0, 0, 0});
  EXPECT_NEAR(cloth.contacts().max_depth_past_thickness, 0.005, 1e-15);
}

}  // namespace
}  // namespace clothlab
