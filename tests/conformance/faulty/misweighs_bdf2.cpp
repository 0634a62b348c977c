// Faulty: bdf2 with the second-order Adams-Bashforth weights (3/2, -1/2) in place of BDF2's
// (4/3, -1/3) and 1/2 in place of 2/3 on the implicit term: still consistent and stable, so
// it converges, but at first order while it declares bdf2's second (numerics.order-* catch it).
#include "bdf2.hpp"

namespace {

constexpr clothlab::builtin::StepWeights misweighed(double step_ratio) {
  return step_ratio == 0.0 ? clothlab::builtin::bdf2_weights(0.0)
                           : clothlab::builtin::StepWeights{1.5, -0.5, 0.5};
}

struct MisweighsBdf2 : clothlab::builtin::MultistepImplicit<misweighed> {
  using MultistepImplicit::MultistepImplicit;
  static constexpr const char* id = "misweighs-bdf2";
  static constexpr const char* name = "BDF2 with Adams-Bashforth's weights";
  static constexpr const char* description = "faulty: declared order 2, actual order 1";
};

}  // namespace

CLOTHLAB_PLUGIN_ENTRY("faulty-misweighs-bdf2", "0.0.1", clothlab::sdk::integrators<MisweighsBdf2>,
                      clothlab::sdk::scenarios<>)
