// A test integrator that crashes (SIGSEGV) on its first step: a sweep must record the case as
// failed and go on.
#include <clothlab/sdk.hpp>

namespace {

struct CrashesInStep {
  static constexpr const char* id = "test-crash";
  static constexpr const char* name = "Test crash";
  static constexpr const char* version = "0.1.0";
  static constexpr const char* description = "writes through a null pointer in step";
  static constexpr uint32_t order = 1, evals_per_step = 0, flags = 0;
  static constexpr std::array<clothlab_param_spec, 0> params{};
  explicit CrashesInStep(const clothlab::sdk::Params&) {}
  template <class Real>
  void prepare(clothlab::sdk::System<Real>&) {}
  template <class Real>
  void step(clothlab::sdk::System<Real>&, double, double) {
    volatile int* volatile target = nullptr;  // volatile: the store may not vanish
    *target = 1;
  }
};

}  // namespace

CLOTHLAB_PLUGIN_ENTRY("clothlab-test-crash", "0.1.0", clothlab::sdk::integrators<CrashesInStep>,
                      clothlab::sdk::scenarios<>)
