// Faulty: symplectic Euler that resolves contacts and allocates a list of the particles they
// moved, only in a step where they moved one: without a collider it never allocates
// (robustness.no-alloc catches it because it steps the cloth against a sphere).
#include <vector>

#include "symplectic_euler.hpp"

struct AllocatesWhereItsContactsAct : clothlab::faulty::SymplecticEulerBase {
  using SymplecticEulerBase::SymplecticEulerBase;
  static constexpr const char* id = "allocates-where-its-contacts-act";
  static constexpr const char* name = "Symplectic Euler allocating where its contacts act";
  static constexpr const char* description =
      "faulty: allocates a list of the particles clothlab.contacts/1 moved";
  static constexpr clothlab_integrator_traits traits{
      sizeof(clothlab_integrator_traits), CLOTHLAB_TRAIT_RESOLVES_CONTACTS, nullptr, nullptr};

  template <class Real>
  void prepare(clothlab::sdk::System<Real>& system) {
    SymplecticEulerBase::prepare(system);
    before_ = system.alloc_vector();
  }

  template <class Real>
  void step(clothlab::sdk::System<Real>& system, double t, double dt) {
    SymplecticEulerBase::step(system, t, dt);
    Real* const before = static_cast<Real*>(before_);
    system.copy(before, system.x());
    system.resolve_contacts(t + dt);
    const Real* const x = system.x();
    std::vector<uint32_t> moved;
    for (uint32_t i = 0; i < system.particle_count(); ++i)
      if (x[i] != before[i]) moved.push_back(i);
    moved_count_ += moved.size();
  }

  void* before_ = nullptr;
  std::size_t moved_count_ = 0;
};

CLOTHLAB_PLUGIN_ENTRY("faulty-allocates-where-its-contacts-act", "0.0.1",
                      clothlab::sdk::integrators<AllocatesWhereItsContactsAct>,
                      clothlab::sdk::scenarios<>)
