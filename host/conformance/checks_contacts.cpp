// contacts.*: an integrator that declares CLOTHLAB_TRAIT_RESOLVES_CONTACTS keeps the cloth out of
// the scene's colliders even where a particle moves farther in one step than a collider is thick:
// a strip of cloth falling at 20 m/s onto a capsule 2.4 cm thick (a character's arm) at 60 Hz
// travels 33 cm per step, so a method that checks only where a step ends lets it through
// (contacts.no-tunnelling; the faulty claims-to-resolve-contacts is caught). The host's
// clothlab.contacts/1 resolves each particle's path over the step or substep
// (resolve_swept_contact), so calling it after each (sub)step is enough. The same holds for a
// collider that moves: a blade 2 mm thick rising at 95 m/s into a resting strip carries it, none
// left on its far side (contacts.moving-collider; the faulty resolves-at-the-step-start, which
// asks for the contacts at the step's start time, is caught), and a box sliding at 2 m/s under a
// strip with friction 0.5 accelerates it at friction x g, then carries it at its own speed
// (contacts.carried-by-a-moving-body).
#include <clothlab/core/contact.hpp>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "check.hpp"
#include "fixtures.hpp"

namespace clothlab::conformance {
namespace {

constexpr double kDt = 1.0 / 60.0;  // s: a game's frame
constexpr double kSpeed = 20.0;     // m/s: a cape's hem whipped past an arm
constexpr double kHeight = 0.05;    // m: the strip's start above the capsule's axis
constexpr int kSteps = 4;

// A horizontal strip of 4 particles along x, level at y = kHeight, over a long thin capsule
// along x at the origin; no gravity, so what moves it is its start velocity.
Scene strip_over_capsule() {
  Scene scene;
  scene.rows = 1;
  scene.cols = 4;
  scene.width = 0.3;
  scene.height = 0.0;
  scene.origin = {-0.15, kHeight, 0.0};
  scene.col_axis = {1, 0, 0};
  scene.row_axis = {0, 0, 1};
  scene.total_mass = 0.04;
  scene.structural = {20.0, 0.01};
  scene.gravity = {0, 0, 0};
  return scene;
}

Collider thin_capsule() {
  Collider capsule;
  capsule.shape = ColliderShape::Capsule;
  capsule.radius = capsule.end_radius = 0.012;
  capsule.half_length = 0.5;
  capsule.thickness = 0.002;
  return capsule;
}

Verdict no_tunnelling(const clothlab_integrator& integrator) {
  const Scene scene = strip_over_capsule();
  Cloth cloth(scene, preferred_precision(integrator), pipeline_for(integrator));
  std::vector<double> x, v;
  cloth.positions(x);
  v.assign(x.size(), 0.0);
  for (std::size_t i = 0; i < v.size(); i += 3) v[i + 1] = -kSpeed;
  cloth.set_state(x, v);
  const Collider capsule = thin_capsule();
  IntegratorInstance instance(integrator, default_values(integrator));
  cloth.set_colliders({&capsule, 1}, 0.0);
  instance.prepare(cloth);
  for (int n = 0; n < kSteps; ++n) {
    cloth.set_colliders({&capsule, 1}, n * kDt);  // as the host does at each step's start
    clothlab_message message{};
    const clothlab_status status =
        integrator.step(instance.handle(), &cloth.system(), n * kDt, kDt, &message);
    require(status == CLOTHLAB_OK,
            "its step " + std::to_string(n + 1) + " failed: " + describe_status(status, message));
    cloth.positions(x);
    for (std::size_t i = 0; i < x.size(); i += 3) {
      const double surface = capsule.radius + capsule.thickness;
      // A millimetre below the thickness band: the band is where contacts put particles.
      if (x[i + 1] < surface - 1e-3) {
        char text[300];
        std::snprintf(text, sizeof text,
                      "particle %zu at y = %.3g m after step %d: it went into or through a "
                      "capsule of radius %g m (its top at y = %g m) that it started %g m above, "
                      "falling at %g m/s with dt = %.4g s",
                      i / 3, x[i + 1], n + 1, capsule.radius, capsule.radius, kHeight, kSpeed, kDt);
        throw CheckFailure(text);
      }
    }
  }
  return {true, "a strip falling at 20 m/s stays on a 2.4 cm capsule over 4 steps of 1/60 s"};
}

// Steps `integrator` from `cloth`'s state against one collider that `collider_at(t)` gives
// (pose and motion at t), set before each step as the host does, calling after_step(step, t)
// after each of `steps` steps of dt.
template <class ColliderAt, class AfterStep>
void step_against(const clothlab_integrator& integrator, Cloth& cloth,
                  const ColliderAt& collider_at, int steps, double dt,
                  const AfterStep& after_step) {
  IntegratorInstance instance(integrator, default_values(integrator));
  Collider collider = collider_at(0.0);
  cloth.set_colliders({&collider, 1}, 0.0);
  instance.prepare(cloth);
  for (int n = 0; n < steps; ++n) {
    clothlab_message message{};
    const clothlab_status status =
        integrator.step(instance.handle(), &cloth.system(), n * dt, dt, &message);
    require(status == CLOTHLAB_OK,
            "its step " + std::to_string(n + 1) + " failed: " + describe_status(status, message));
    collider = collider_at((n + 1) * dt);
    cloth.set_colliders({&collider, 1}, (n + 1) * dt);
    after_step(n + 1, (n + 1) * dt);
  }
}

constexpr double kBladeSpeed = 95.0;  // m/s: near the fastest pose the host accepts
constexpr double kBladeDt = 1e-3;     // s

// A box 2 mm thick (half height 1 mm), kept 2 mm clear of, wider than the strip, its top 3 cm
// below the strip at t = 0 and rising at kBladeSpeed.
Collider rising_blade(double t) {
  Collider blade;
  blade.shape = ColliderShape::Box;
  blade.half_extents = {0.5, 0.001, 0.5};
  blade.thickness = 0.002;
  blade.motion.velocity = {0, kBladeSpeed, 0};
  blade.pose.position = {0, kHeight - 0.031 + kBladeSpeed * t, 0};
  return blade;
}

Verdict moving_collider(const clothlab_integrator& integrator) {
  Cloth cloth(strip_over_capsule(), preferred_precision(integrator), pipeline_for(integrator));
  std::vector<double> x;
  step_against(integrator, cloth, rising_blade, 5, kBladeDt, [&](int step, double t) {
    cloth.positions(x);
    const double top = rising_blade(t).pose.position[1] + 0.001;
    for (std::size_t i = 0; i < x.size(); i += 3)
      // A millimetre inside the thickness band: the band is where contacts put particles.
      if (x[i + 1] < top + 0.001) {
        char text[300];
        std::snprintf(text, sizeof text,
                      "particle %zu at y = %.4g m after step %d: a box 2 mm thick rising at %g m/s "
                      "(its top at y = %.4g m) passed it, dt = %g s",
                      i / 3, x[i + 1], step, kBladeSpeed, top, kBladeDt);
        throw CheckFailure(text);
      }
  });
  return {true, "a blade 2 mm thick rising at 95 m/s carries a resting strip, none left behind"};
}

constexpr double kBodySpeed = 2.0;  // m/s
constexpr double kBodyFriction = 0.5;

// A wide box sliding along x at kBodySpeed, its top at y = 0.
Collider sliding_box(double t) {
  Collider box;
  box.shape = ColliderShape::Box;
  box.half_extents = {2.0, 0.1, 2.0};
  box.thickness = 0.002;
  box.friction = kBodyFriction;
  box.motion.velocity = {kBodySpeed, 0, 0};
  box.pose.position = {kBodySpeed * t, -0.1, 0};
  return box;
}

double mean_velocity_along_x(const Cloth& cloth) {
  std::vector<double> v;
  cloth.velocities(v);
  double sum = 0;
  for (std::size_t i = 0; i < v.size(); i += 3) sum += v[i];
  return sum / static_cast<double>(v.size() / 3);
}

// Coulomb friction on a strip resting under gravity accelerates it at friction x g relative to
// the box until it moves with it (after 0.41 s): checked at 0.2 s, halfway, where a method that
// loses part of each step's normal velocity into the box (and so part of the friction that goes
// with it) lags, though it may still catch up by 1 s.
Verdict carried_by_a_moving_body(const clothlab_integrator& integrator) {
  Scene scene = strip_over_capsule();
  scene.origin[1] = 0.002;  // resting on the box's thickness band
  scene.gravity = {0, -9.81, 0};
  Cloth cloth(scene, preferred_precision(integrator), pipeline_for(integrator));
  constexpr double dt = 1e-3;
  constexpr int steps = 1000;
  constexpr int halfway = 200;
  double halfway_mean = 0;
  step_against(integrator, cloth, sliding_box, steps, dt, [&](int step, double) {
    if (step == halfway) halfway_mean = mean_velocity_along_x(cloth);
  });
  const double accelerated = kBodyFriction * 9.81 * halfway * dt;
  if (!(std::abs(halfway_mean - accelerated) <= 0.05 * accelerated)) {
    char text[300];
    std::snprintf(text, sizeof text,
                  "the strip's mean velocity along the box's motion is %.4g m/s after %g s on a "
                  "box sliding at %g m/s with friction %g: allowed within 5 %% of friction x g x "
                  "t = %.4g m/s",
                  halfway_mean, halfway * dt, kBodySpeed, kBodyFriction, accelerated);
    throw CheckFailure(text);
  }
  const double mean = mean_velocity_along_x(cloth);
  if (!(std::abs(mean - kBodySpeed) <= 0.05 * kBodySpeed)) {
    char text[300];
    std::snprintf(text, sizeof text,
                  "the strip's mean velocity along the box's motion is %.4g m/s after %g s on a "
                  "box sliding at %g m/s with friction %g: allowed within 5 %% of it",
                  mean, steps * dt, kBodySpeed, kBodyFriction);
    throw CheckFailure(text);
  }
  char text[200];
  std::snprintf(text, sizeof text,
                "a strip on a box sliding at 2 m/s with friction 0.5: %.4g m/s after 0.2 s "
                "(friction x g x t = %.4g), %.4g after 1 s",
                halfway_mean, accelerated, mean);
  return {true, text};
}

}  // namespace

std::vector<Check> contacts_checks(const clothlab_integrator& integrator) {
  if (!has_trait(integrator, CLOTHLAB_TRAIT_RESOLVES_CONTACTS)) return {};
  const clothlab_integrator* c = &integrator;
  return {
      {c->id, "contacts.no-tunnelling", [c] { return no_tunnelling(*c); }},
      {c->id, "contacts.moving-collider", [c] { return moving_collider(*c); }},
      {c->id, "contacts.carried-by-a-moving-body", [c] { return carried_by_a_moving_body(*c); }}};
}

}  // namespace clothlab::conformance
