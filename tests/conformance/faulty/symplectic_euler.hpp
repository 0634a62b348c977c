// The honest core most faulty plugins start from: symplectic Euler on the host's vectors.
// Each faulty plugin changes one thing about it.
#pragma once

#include <array>
#include <clothlab/sdk.hpp>

namespace clothlab::faulty {

struct SymplecticEulerBase {
  static constexpr const char* version = "0.0.1";
  static constexpr uint32_t order = 1;
  static constexpr uint32_t evals_per_step = 1;
  static constexpr uint32_t flags = CLOTHLAB_INTEGRATOR_USES_VELOCITY_FORCES;
  static constexpr std::array<clothlab_param_spec, 0> params{};

  explicit SymplecticEulerBase(const sdk::Params&) {}

  template <class Real>
  void prepare(sdk::System<Real>& system) {
    acceleration_ = system.alloc_vector();
  }

  template <class Real>
  void step(sdk::System<Real>& system, double t, double dt) {
    Real* a = static_cast<Real*>(acceleration_);
    system.acceleration(t, system.x(), system.v(), a);
    system.axpy(system.v(), dt, a);
    system.axpy(system.x(), dt, system.v());
  }

  void* acceleration_ = nullptr;
};

}  // namespace clothlab::faulty
