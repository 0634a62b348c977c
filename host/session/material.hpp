// A cloth material as the configuration gives it (keys material.*; configs/materials/README.md):
// the core's per-area ClothMaterial, which the core turns into any cloth's masses and springs
// (clothlab/core/cloth_material.hpp), with its label and where it was set.
#pragma once

#include <clothlab/core/cloth_material.hpp>
#include <string>
#include <vector>

#include "settings.hpp"

namespace clothlab::cli {

struct Material : ClothMaterial {
  std::string name;    // label for reports ("cotton"); may be empty
  std::string source;  // where the first material key was set, for messages
};

// Throws InputError when `user_settings` (the scenario settings given) set a value the material
// decides under the built-in scenarios' names (mass, <family>.ks, <family>.kd): one or the
// other, never silently both.
void check_no_material_conflict(const Material& material,
                                const std::vector<Setting>& user_settings);

}  // namespace clothlab::cli
