// Faulty: symplectic Euler declaring CLOTHLAB_TRAIT_MOVES_ATTACHMENTS that never moves them:
// the attached particles stay where they were pinned (attachments.follow-* catches it).
#include "symplectic_euler.hpp"

struct IgnoresAttachments : clothlab::faulty::SymplecticEulerBase {
  using SymplecticEulerBase::SymplecticEulerBase;
  static constexpr const char* id = "ignores-attachments";
  static constexpr const char* name = "Symplectic Euler ignoring moving attachments";
  static constexpr const char* description =
      "faulty: declares that it moves attachments, leaves them where they were pinned";
  static constexpr clothlab_integrator_traits traits{
      sizeof(clothlab_integrator_traits), CLOTHLAB_TRAIT_MOVES_ATTACHMENTS, nullptr, nullptr};
};

CLOTHLAB_PLUGIN_ENTRY("faulty-ignores-attachments", "0.0.1",
                      clothlab::sdk::integrators<IgnoresAttachments>, clothlab::sdk::scenarios<>)
