// Faulty: writes one element past a heap block in step. Built with AddressSanitizer, it is the
// plugin author's case of tests/conformance/CMakeLists.txt: the Release runner, run with the
// sanitizer runtime preloaded, must put ASan's report into the failed check's reason.
#include <memory>

#include "symplectic_euler.hpp"

struct OverflowsHeapInStep : clothlab::faulty::SymplecticEulerBase {
  explicit OverflowsHeapInStep(const clothlab::sdk::Params& params)
      : SymplecticEulerBase(params), scratch_(new double[4]) {}
  static constexpr const char* id = "overflows-heap-in-step";
  static constexpr const char* name = "Integrator that overflows a heap block";
  static constexpr const char* description = "faulty: writes past a heap block in step";

  template <class Real>
  void step(clothlab::sdk::System<Real>& system, double t, double dt) {
    double* volatile block = scratch_.get();  // volatile: the store may not vanish
    block[4] = dt;
    SymplecticEulerBase::step(system, t, dt);
  }

  std::unique_ptr<double[]> scratch_;
};

CLOTHLAB_PLUGIN_ENTRY("faulty-overflows-heap-in-step", "0.0.1",
                      clothlab::sdk::integrators<OverflowsHeapInStep>, clothlab::sdk::scenarios<>)
