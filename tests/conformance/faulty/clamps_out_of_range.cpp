// Faulty: clamps a parameter value outside its range into the range (and a NaN to the minimum)
// instead of refusing it; params.out-of-range catches it: a silent default hides the
// caller's mistake.
#include <algorithm>
#include <cmath>
#include <vector>

#include "edited_library.hpp"
#include "substeps_euler.hpp"

struct ClampsOutOfRange : clothlab::faulty::SubstepsEulerBase {
  using SubstepsEulerBase::SubstepsEulerBase;
  static constexpr const char* id = "clamps-out-of-range";
  static constexpr const char* name = "Symplectic Euler that clamps its parameters";
  static constexpr const char* description = "faulty: out-of-range values are clamped silently";
};

namespace {
decltype(clothlab_integrator::create) sdk_create = nullptr;

clothlab_status create_clamped(const clothlab_param_value* values, uint32_t count, void** out,
                               clothlab_message* error) {
  std::vector<clothlab_param_value> clamped(values, values + count);
  for (uint32_t i = 0; i < count && i < ClampsOutOfRange::params.size(); ++i) {
    const clothlab_param_spec& spec = ClampsOutOfRange::params[i];
    double& value = clamped[i].v[0];
    value = std::isnan(value) ? spec.min_value : std::clamp(value, spec.min_value, spec.max_value);
  }
  return sdk_create(clamped.data(), count, out, error);
}
}  // namespace

extern "C" CLOTHLAB_EXPORT const clothlab_plugin_descriptor* clothlab_plugin_entry(void) {
  return clothlab::faulty::edited_library<ClampsOutOfRange>("faulty-clamps-out-of-range",
                                                            [](clothlab_integrator& integrator) {
                                                              sdk_create = integrator.create;
                                                              integrator.create = create_clamped;
                                                            });
}
