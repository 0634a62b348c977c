// Faulty: symplectic Euler that resolves contacts and allocates a list of the particles they
// moved, only in a step where they moved one: without a collider it never allocates
// (robustness.no-alloc catches it because it steps the cloth against a sphere).
#include <vector>

#include "symplectic_euler.hpp"

struct AllocatesWhereItsContactsAct
    : clothlab::faulty::ContactsAroundEulerBase<AllocatesWhereItsContactsAct> {
  using ContactsAroundEulerBase::ContactsAroundEulerBase;
  static constexpr const char* id = "allocates-where-its-contacts-act";
  static constexpr const char* name = "Symplectic Euler allocating where its contacts act";
  static constexpr const char* description =
      "faulty: allocates a list of the particles clothlab.contacts/1 moved";

  template <class Real>
  static const Real* kept(clothlab::sdk::System<Real>& system) {
    return system.x();
  }

  template <class Real>
  void after_contacts(clothlab::sdk::System<Real>& system, const Real* before) {
    const Real* const x = system.x();
    std::vector<uint32_t> moved;
    for (uint32_t i = 0; i < system.particle_count(); ++i)
      if (x[i] != before[i]) moved.push_back(i);
    moved_count_ += moved.size();
  }

  std::size_t moved_count_ = 0;
};

CLOTHLAB_PLUGIN_ENTRY("faulty-allocates-where-its-contacts-act", "0.0.1",
                      clothlab::sdk::integrators<AllocatesWhereItsContactsAct>,
                      clothlab::sdk::scenarios<>)
