// The bdf2 plugin: bdf2.hpp's method with BDF2's own weights.
#include "bdf2.hpp"

namespace clothlab::builtin {

struct Bdf2 : MultistepImplicit<bdf2_weights> {
  using MultistepImplicit::MultistepImplicit;
};

}  // namespace clothlab::builtin

CLOTHLAB_PLUGIN_ENTRY("clothlab-builtin-bdf2", "1.0.0",
                      clothlab::sdk::integrators<clothlab::builtin::Bdf2>,
                      clothlab::sdk::scenarios<>)
