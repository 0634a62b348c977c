#include "scene_air.hpp"

#include <clothlab/ext/air.h>

#include <clothlab/host/errors.hpp>
#include <stdexcept>
#include <string>

namespace clothlab::cli {

Air scene_air(const host::ScenarioPlugin& scenario, const host::ScenarioInstance& instance) {
  const auto* table =
      static_cast<const clothlab_air_extension*>(scenario.extension(CLOTHLAB_EXT_AIR));
  if (table == nullptr) return {};
  const std::string owner = "scenario " + std::string(scenario.info().id);
  clothlab_air raw{};
  raw.struct_size = sizeof raw;
  clothlab_message message{};
  const clothlab_status status = table->describe(instance.get(), &raw, &message);
  if (status != CLOTHLAB_OK)
    throw host::PluginError(status, owner + ": air: " + host::one_line(message.text));
  try {
    return air_from_abi(raw);
  } catch (const std::invalid_argument& error) {
    throw host::InputError(owner + ": " + error.what());
  }
}

}  // namespace clothlab::cli
