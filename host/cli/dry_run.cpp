#include "dry_run.hpp"

#include <unistd.h>

#include <clothlab/host/errors.hpp>
#include <nlohmann/json.hpp>

#include "isolation.hpp"
#include "simulation.hpp"

namespace clothlab::cli {

std::string check_single_run(const RunConfig& config, const host::PluginSearchPath& search_path) {
  // Creating instances is plugin code: in a child, like the run itself.
  const nlohmann::json described = run_isolated(
      [&] {
        const Simulation simulation(config, search_path);
        const Cloth& cloth = simulation.cloth();
        return nlohmann::json{{"integrator", simulation.integrator_id()},
                              {"scenario", simulation.scenario_id()},
                              {"rows", cloth.scene().rows},
                              {"cols", cloth.scene().cols}};
      },
      config.timeout_s);
  return described["integrator"].get<std::string>() + " on " +
         described["scenario"].get<std::string>() + ", " +
         std::to_string(described["rows"].get<uint32_t>()) + "x" +
         std::to_string(described["cols"].get<uint32_t>()) + " particles";
}

void check_creatable_folder(const std::filesystem::path& folder, const std::string& source) {
  std::filesystem::path existing = std::filesystem::absolute(folder);
  while (!std::filesystem::exists(existing) && existing.has_relative_path())
    existing = existing.parent_path();
  if (!std::filesystem::is_directory(existing))
    throw host::InputError(source + " " + folder.string() + ": " + existing.string() +
                           " is not a folder; allowed: a folder path");
  if (::access(existing.c_str(), W_OK | X_OK) != 0)
    throw host::InputError(source + " " + folder.string() + ": folder " + existing.string() +
                           " is not writable");
}

}  // namespace clothlab::cli
