#include "material.hpp"

#include <clothlab/host/errors.hpp>

namespace clothlab::cli {

namespace {

// The built-in scenarios' parameters whose values the material decides.
constexpr const char* decided_keys[] = {"mass",     "structural.ks", "structural.kd", "shear.ks",
                                        "shear.kd", "flexion.ks",    "flexion.kd"};

}  // namespace

void check_no_material_conflict(const Material& material,
                                const std::vector<Setting>& user_settings) {
  for (const Setting& setting : user_settings)
    for (const char* key : decided_keys)
      if (setting.key == key)
        throw host::InputError(setting.source + ": scenario." + setting.key + " = " +
                               setting.value + " conflicts with the material set at " +
                               material.source +
                               "; allowed: a material or per-spring values, not both");
}

}  // namespace clothlab::cli
