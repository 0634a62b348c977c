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

// The traits of a faulty plugin that declares it resolves contacts.
inline constexpr clothlab_integrator_traits kResolvesContactsTraits{
    sizeof(clothlab_integrator_traits), CLOTHLAB_TRAIT_RESOLVES_CONTACTS, nullptr, nullptr};

// Symplectic Euler that resolves the contacts at the step's end, keeping a copy of one state
// vector from just before them (`Faulty::kept`): the faulty plugin's `after_contacts` decides
// what it does with the copy.
template <class Faulty>
struct ContactsAroundEulerBase : SymplecticEulerBase {
  using SymplecticEulerBase::SymplecticEulerBase;
  static constexpr clothlab_integrator_traits traits = kResolvesContactsTraits;

  template <class Real>
  void prepare(sdk::System<Real>& system) {
    SymplecticEulerBase::prepare(system);
    before_contacts_ = system.alloc_vector();
  }

  template <class Real>
  void step(sdk::System<Real>& system, double t, double dt) {
    SymplecticEulerBase::step(system, t, dt);
    Real* const kept = static_cast<Real*>(before_contacts_);
    system.copy(kept, Faulty::kept(system));
    system.resolve_contacts(t + dt);
    static_cast<Faulty&>(*this).after_contacts(system, kept);
  }

  void* before_contacts_ = nullptr;
};

}  // namespace clothlab::faulty
