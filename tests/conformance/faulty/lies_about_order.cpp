// Faulty: a first-order method that declares second order (numerics.order-* catch it).
#include "symplectic_euler.hpp"

struct LiesAboutOrder : clothlab::faulty::SymplecticEulerBase {
  using SymplecticEulerBase::SymplecticEulerBase;
  static constexpr const char* id = "lies-about-order";
  static constexpr const char* name = "Symplectic Euler claiming order 2";
  static constexpr const char* description = "faulty: declared order 2, actual order 1";
  static constexpr uint32_t order = 2;
};

CLOTHLAB_PLUGIN_ENTRY("faulty-lies-about-order", "0.0.1",
                      clothlab::sdk::integrators<LiesAboutOrder>, clothlab::sdk::scenarios<>)
