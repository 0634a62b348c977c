// Faulty: the range of substeps was raised to start at 1, its default stayed 0;
// descriptor.params catches the schema that contradicts itself.
#include "substeps_euler.hpp"

struct DefaultOutsideRange : clothlab::faulty::SubstepsEulerBase {
  using SubstepsEulerBase::SubstepsEulerBase;
  static constexpr const char* id = "default-outside-range";
  static constexpr const char* name = "Symplectic Euler whose default is outside its range";
  static constexpr const char* description = "faulty: substeps default 0, range [1, 64]";
  static constexpr std::array<clothlab_param_spec, 1> params{
      clothlab::sdk::int_param("substeps", 0, 1, 64, "equal substeps per step")};
};

CLOTHLAB_PLUGIN_ENTRY("faulty-default-outside-range", "0.0.1",
                      clothlab::sdk::integrators<DefaultOutsideRange>, clothlab::sdk::scenarios<>)
