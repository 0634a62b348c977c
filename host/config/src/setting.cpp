#include "clothlab/config/setting.hpp"

#include <clothlab/host/errors.hpp>

namespace clothlab::config {

std::string canonical_key(const std::string& key) {
  if (key == "integrator" || key == "scenario") return key + ".plugin";
  return key;
}

void check_one_length(const std::vector<Setting>& layer, const std::string& layer_name) {
  const Setting* steps = nullptr;
  const Setting* duration = nullptr;
  for (const Setting& setting : layer) {
    if (setting.key == "steps") steps = &setting;
    if (setting.key == "duration") duration = &setting;
  }
  if (steps != nullptr && duration != nullptr)
    throw host::InputError(duration->source + ": duration = " + duration->value +
                           " conflicts with " + steps->source + ": steps = " + steps->value +
                           " in the " + layer_name + "; allowed: steps or duration, not both");
}

}  // namespace clothlab::config
