// Faulty: one evaluation per step, but it declares a two-stage scheme as its table
// (descriptor.extensions catches the mismatch).
#include "symplectic_euler.hpp"

struct MisdeclaresScheme : clothlab::faulty::SymplecticEulerBase {
  using SymplecticEulerBase::SymplecticEulerBase;
  static constexpr const char* id = "misdeclares-scheme";
  static constexpr const char* name = "Symplectic Euler declaring the midpoint table";
  static constexpr const char* description = "faulty: explicit scheme of 2 stages, 1 evaluation";
  static constexpr clothlab::sdk::RknScheme<2> midpoint{
      {0.0, 0.5}, {0.0, 0.5}, {0.0, 0.0, 0.0, 0.0}, {0.0, 0.0, 0.5, 0.0}, {0.5, 0.0}, {0.0, 1.0}};
  static constexpr clothlab_rkn_scheme raw_scheme = midpoint.raw();
  static constexpr clothlab_explicit_scheme explicit_scheme =
      clothlab::sdk::explicit_scheme_of(raw_scheme);
};

CLOTHLAB_PLUGIN_ENTRY("faulty-misdeclares-scheme", "0.0.1",
                      clothlab::sdk::integrators<MisdeclaresScheme>, clothlab::sdk::scenarios<>)
