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
      resolve_swept_contact(colliders, colliders, from, p.x, p.v);
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
    cloth.set_colliders({&floor, 1}, 0.0);
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
  cloth.set_colliders(both, 0.0);
  cloth.set_state({0, -0.015, 0}, {0, 0, 0});
  EXPECT_NEAR(cloth.contacts().max_penetration, 0.015, 1e-15);
  EXPECT_EQ(cloth.contacts().max_depth_past_thickness, 0.0);
  cloth.set_state({5, 0.09, 0}, {0, 0, 0});
  EXPECT_NEAR(cloth.contacts().max_depth_past_thickness, 0.005, 1e-15);
}

// A blade: a box 2 mm thick (half height 1 mm), wide enough to cover a small cloth, its faces
// normal to y, kept 2 mm clear of.
Collider blade(double speed_up) {
  Collider box;
  box.shape = ColliderShape::Box;
  box.half_extents = {5.0, 0.001, 5.0};
  box.thickness = 0.002;
  box.pose.position = {0, -0.03, 0};
  box.motion.velocity = {0, speed_up, 0};
  return box;
}

// A level 4 x 4 cloth at rest at y = 0 (no springs, no gravity: only the contacts move it), and a
// blade rising through it at each speed, 1 ms steps, the contacts resolved at each step's end
// as a force-based integrator does. With the blade's motion swept, no particle ends a step below
// the blade's top (on its far side) and none is counted as crossing; with the blade's pose set
// at each step's start and held (the contacts before colliders had velocities), it passes
// through the cloth and the crossings say so.
TEST(ContactResolution, AThinBladeRisingFastDoesNotPassThroughARestingCloth) {
  for (const double speed : {20.0, 50.0, 95.0})
    for (const bool swept : {true, false}) {
      Scene scene = testing::bare_scene(4, 4);
      scene.row_axis = {0, 0, 1};  // level, in the x-z plane over the blade
      Cloth cloth(scene, Precision::Float64, PipelineOptions{});
      const clothlab_system& system = cloth.system();
      const auto* contacts = static_cast<const clothlab_contacts_extension*>(
          clothlab_system_extension(&system, CLOTHLAB_EXT_CONTACTS));
      constexpr double dt = 1e-3;
      uint64_t crossings = 0;
      bool far_side = false;
      // As the host does: the blade at each step's start, set after the step before.
      const auto set_blade = [&](double t) {
        Collider now = blade(speed).advanced(t);
        if (!swept) now.motion = {};
        cloth.set_colliders({&now, 1}, t);
      };
      set_blade(0);
      for (int step = 0; step < 5; ++step) {
        const double t = step * dt;
        ASSERT_EQ(contacts->resolve(system.context, t + dt, system.x, system.v), CLOTHLAB_OK);
        set_blade(t + dt);
        crossings += cloth.contacts().particles_crossed;
        const double top = blade(speed).advanced(t + dt).pose.position[1] + 0.001;
        std::vector<double> x;
        cloth.positions(x);
        for (std::size_t i = 1; i < x.size(); i += 3) far_side = far_side || x[i] < top;
      }
      EXPECT_EQ(far_side, !swept) << speed << " m/s";
      EXPECT_EQ(crossings > 0, !swept) << speed << " m/s";
      if (swept) {
        std::vector<double> v;
        cloth.velocities(v);
        EXPECT_NEAR(v[1], speed, 1e-9) << "carried at the blade's speed";
      }
    }
}

// A particle resting on a floor that slides sideways at 2 m/s, friction 0.5: Coulomb friction
// on the velocity relative to the floor accelerates it at mu g until it moves with the floor
// (after 2 / (0.5 g) = 0.41 s), and it stays with it.
TEST(ContactResolution, FrictionCarriesAParticleWithAMovingBody) {
  Collider floor = ground(0.5, 0.0);
  floor.motion.velocity = {2.0, 0, 0};
  const double h = 1e-3;
  Particle p{{0, 0, 0}, {0, 0, 0}};
  double speed_at_0_2_s = 0;
  for (int step = 1; step <= 1000; ++step) {
    p = fall(p, {&floor, 1}, h, 1);
    if (step == 200) speed_at_0_2_s = p.v[0];
  }
  EXPECT_NEAR(speed_at_0_2_s, 0.5 * g * 0.2, 2 * g * h);
  EXPECT_NEAR(p.v[0], 2.0, 1e-12);
  EXPECT_NEAR(p.x[1], 0.0, 1e-12);
}

// The motion that takes one pose to another in dt carries the first onto the second, turns
// included; a velocity its poses do not follow is refused.
TEST(ContactResolution, AMotionBetweenTwoPosesCarriesTheFirstOntoTheSecond) {
  Collider box;
  box.shape = ColliderShape::Box;
  box.half_extents = {0.5, 0.1, 0.2};
  box.pose.position = {1, 2, 3};
  const double angle = 0.3;
  Pose after;
  after.position = {1.2, 1.9, 3.05};
  after.orientation = {std::cos(angle / 2), 0, 0, std::sin(angle / 2)};
  box.motion = motion_between(box.pose, after, 0.01);
  EXPECT_NEAR(box.motion.angular_velocity[2], angle / 0.01, 1e-9);
  const Collider moved = box.advanced(0.01);
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(moved.pose.position[k], after.position[k], 1e-12);
  for (int k = 0; k < 4; ++k) EXPECT_NEAR(moved.pose.orientation[k], after.orientation[k], 1e-12);
  // A point on the axis of turn moves with the frame; one 1 m off it adds angle / dt.
  EXPECT_NEAR(box.velocity_at({1, 3, 3})[0], 20.0 - angle / 0.01, 1e-9);

  EXPECT_NO_THROW(check_motion_agrees(box.motion, box.motion));
  Motion backwards = box.motion;
  for (double& component : backwards.velocity) component = -component;
  EXPECT_THROW(check_motion_agrees(backwards, box.motion), std::invalid_argument);
  try {
    check_motion_agrees(Motion{{20, 0, 0}, {}}, Motion{});
    ADD_FAILURE() << "a velocity of 20 m/s on a still body passed";
  } catch (const std::invalid_argument& error) {
    EXPECT_STREQ(error.what(),
                 "velocity 20 m/s, its poses move at 0 m/s (20 apart): allowed within 11 m/s of "
                 "them");
  }
}

}  // namespace
}  // namespace clothlab
