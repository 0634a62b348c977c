// Faulty: bdf2 restarting each particle the contacts moved as if it had moved at its new
// velocity for a step, so it loses the third of each step's velocity change its history
// carries: a strip resting on a sliding box meets it slower each step and friction drags it at
// two thirds of friction x g, though it still moves with the box after 1 s
// (contacts.carried-by-a-moving-body catches it at 0.2 s).
#include "bdf2.hpp"

namespace {

struct RestartsBdf2AtContacts
    : clothlab::builtin::MultistepImplicit<clothlab::builtin::bdf2_weights,
                                           clothlab::builtin::ContactHistory::kRestarted> {
  using MultistepImplicit::MultistepImplicit;
  static constexpr const char* id = "restarts-bdf2-at-contacts";
  static constexpr const char* name = "BDF2 restarted where the contacts moved the cloth";
  static constexpr const char* description =
      "faulty: drops its history's share of the forces on a particle in contact";
};

}  // namespace

CLOTHLAB_PLUGIN_ENTRY("faulty-restarts-bdf2-at-contacts", "0.0.1",
                      clothlab::sdk::integrators<RestartsBdf2AtContacts>,
                      clothlab::sdk::scenarios<>)
