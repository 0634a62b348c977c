// Faulty: declares order 0 (meant as "unknown"); descriptor.order catches it: hosts compare
// measured orders with it.
#include "symplectic_euler.hpp"

struct DeclaresOrderZero : clothlab::faulty::SymplecticEulerBase {
  using SymplecticEulerBase::SymplecticEulerBase;
  static constexpr const char* id = "declares-order-zero";
  static constexpr const char* name = "Symplectic Euler declaring order 0";
  static constexpr const char* description = "faulty: order 0";
  static constexpr uint32_t order = 0;
};

CLOTHLAB_PLUGIN_ENTRY("faulty-declares-order-zero", "0.0.1",
                      clothlab::sdk::integrators<DeclaresOrderZero>, clothlab::sdk::scenarios<>)
