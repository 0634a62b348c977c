// Faulty: dereferences a null pointer in step (the runner reports "crashed: signal 11").
#include "symplectic_euler.hpp"

struct SegfaultsInStep : clothlab::faulty::SymplecticEulerBase {
  using SymplecticEulerBase::SymplecticEulerBase;
  static constexpr const char* id = "segfaults-in-step";
  static constexpr const char* name = "Integrator that segfaults";
  static constexpr const char* description = "faulty: writes through a null pointer in step";

  template <class Real>
  void step(clothlab::sdk::System<Real>&, double, double) {
    volatile int* volatile target = nullptr;  // volatile: neither load nor store may vanish
    *target = 1;
  }
};

CLOTHLAB_PLUGIN_ENTRY("faulty-segfaults-in-step", "0.0.1",
                      clothlab::sdk::integrators<SegfaultsInStep>, clothlab::sdk::scenarios<>)
