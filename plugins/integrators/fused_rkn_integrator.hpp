// What every integrator that the host steps by its fused Runge-Kutta-Nystrom sweep shares: the
// table declared as data (clothlab.explicit-scheme/1, from which the host derives the cost and
// the stability limit), the sweep's storage reserved in `prepare`, one step_rkn per step, then
// the attachments moved to their targets at the step's end (clothlab.attachment-targets/1) and
// the host's contact resolution (clothlab.contacts/1) on the step's end state.
// A method is its table: `struct Rk4 : FusedRknIntegrator<rk4_scheme> { ... }`.
#pragma once

#include <clothlab/sdk.hpp>
#include <cstddef>

#include "scratch_vectors.hpp"

namespace clothlab::builtin {

template <std::size_t Stages>
constexpr std::size_t stages_of(const sdk::RknScheme<Stages>&) {
  return Stages;
}

template <const auto& Scheme>
class FusedRknIntegrator {
 public:
  static constexpr std::size_t stages = stages_of(Scheme);
  static constexpr uint32_t evals_per_step = static_cast<uint32_t>(stages);
  static constexpr uint32_t flags = CLOTHLAB_INTEGRATOR_USES_VELOCITY_FORCES;
  static constexpr clothlab_rkn_scheme raw_scheme = Scheme.raw();
  static constexpr clothlab_explicit_scheme explicit_scheme = sdk::explicit_scheme_of(raw_scheme);
  static constexpr clothlab_integrator_traits traits{
      sizeof(clothlab_integrator_traits),
      CLOTHLAB_TRAIT_RESOLVES_CONTACTS | CLOTHLAB_TRAIT_MOVES_ATTACHMENTS, nullptr, nullptr};

  template <class Real>
  void prepare(sdk::System<Real>& system) {
    prepared_for_.allocate(system);
    system.reserve_rkn(static_cast<uint32_t>(stages));
  }

  template <class Real>
  void step(sdk::System<Real>& system, double t, double dt) {
    (void)prepared_for_.bind(system);
    if (dt == 0.0) return;
    system.step_rkn(t, dt, Scheme);
    // The stages saw the attachments where the step started (as the colliders).
    system.move_attachments(t + dt);
    system.resolve_contacts(t + dt);
  }

 private:
  ScratchVectors<0> prepared_for_;  // no vectors: remembers the system
};

}  // namespace clothlab::builtin
