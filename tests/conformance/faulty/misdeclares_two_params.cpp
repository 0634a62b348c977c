// Faulty: two parameter specs the loader once accepted and only the conformance runner refused,
// a whole-number default of 2.5 and a bool ranging over [0, 2]. The one descriptor validator
// finds both: the loader refuses on the first, descriptor.params reports both.
#include "substeps_euler.hpp"

struct MisdeclaresTwoParams : clothlab::faulty::SubstepsEulerBase {
  using SubstepsEulerBase::SubstepsEulerBase;
  static constexpr const char* id = "misdeclares-two-params";
  static constexpr const char* name = "Symplectic Euler with two malformed parameter specs";
  static constexpr const char* description = "faulty: substeps default 2.5, a bool in [0, 2]";
  static constexpr std::array<clothlab_param_spec, 2> params{
      clothlab::sdk::int_param("substeps", 2.5, 1, 64, "equal substeps per step"),
      clothlab_param_spec{sizeof(clothlab_param_spec),
                          CLOTHLAB_PARAM_BOOL,
                          "verbose",
                          "a bool whose range is not [0, 1]",
                          "",
                          {0.0, 0.0, 0.0},
                          0.0,
                          2.0}};
};

CLOTHLAB_PLUGIN_ENTRY("faulty-misdeclares-two-params", "0.0.1",
                      clothlab::sdk::integrators<MisdeclaresTwoParams>, clothlab::sdk::scenarios<>)
