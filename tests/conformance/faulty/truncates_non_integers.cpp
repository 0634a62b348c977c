// Faulty: truncates a non-integer value of its integer parameter (substeps = 1.5 runs 1
// substep) instead of refusing it; params.wrong-type catches it.
#include <cmath>
#include <vector>

#include "edited_library.hpp"
#include "substeps_euler.hpp"

struct TruncatesNonIntegers : clothlab::faulty::SubstepsEulerBase {
  using SubstepsEulerBase::SubstepsEulerBase;
  static constexpr const char* id = "truncates-non-integers";
  static constexpr const char* name = "Symplectic Euler that truncates its substeps";
  static constexpr const char* description = "faulty: substeps = 1.5 is taken as 1";
};

namespace {
decltype(clothlab_integrator::create) sdk_create = nullptr;

clothlab_status create_truncated(const clothlab_param_value* values, uint32_t count, void** out,
                                 clothlab_message* error) {
  std::vector<clothlab_param_value> truncated(values, values + count);
  if (!truncated.empty()) truncated[0].v[0] = std::trunc(truncated[0].v[0]);
  return sdk_create(truncated.data(), count, out, error);
}
}  // namespace

extern "C" CLOTHLAB_EXPORT const clothlab_plugin_descriptor* clothlab_plugin_entry(void) {
  return clothlab::faulty::edited_library<TruncatesNonIntegers>(
      "faulty-truncates-non-integers", [](clothlab_integrator& integrator) {
        sdk_create = integrator.create;
        integrator.create = create_truncated;
      });
}
