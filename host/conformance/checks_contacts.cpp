// contacts.*: an integrator that declares CLOTHLAB_TRAIT_RESOLVES_CONTACTS keeps the cloth out of
// the scene's colliders even where a particle moves farther in one step than a collider is thick:
// a strip of cloth falling at 20 m/s onto a capsule 2.4 cm thick (a character's arm) at 60 Hz
// travels 33 cm per step, so a method that checks only where a step ends lets it through
// (contacts.no-tunnelling; the faulty claims-to-resolve-contacts is caught). The host's
// clothlab.contacts/1 resolves each particle's path over the step or substep
// (resolve_swept_contact), so calling it after each (sub)step is enough.
#include <clothlab/core/contact.hpp>
#include <cmath>
#include <cstdio>
#include <string>

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
  cloth.set_colliders({&capsule, 1});
  instance.prepare(cloth);
  for (int n = 0; n < kSteps; ++n) {
    cloth.set_colliders({&capsule, 1});  // as the host does at each step's start
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

}  // namespace

std::vector<Check> contacts_checks(const clothlab_integrator& integrator) {
  if (!has_trait(integrator, CLOTHLAB_TRAIT_RESOLVES_CONTACTS)) return {};
  const clothlab_integrator* c = &integrator;
  return {{c->id, "contacts.no-tunnelling", [c] { return no_tunnelling(*c); }}};
}

}  // namespace clothlab::conformance
