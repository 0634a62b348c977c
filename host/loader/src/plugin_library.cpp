#include "clothlab/host/plugin_library.hpp"

#include <map>

#include "clothlab/host/descriptor_findings.hpp"
#include "clothlab/host/errors.hpp"
#include "clothlab/host/library_handle.hpp"

namespace fs = std::filesystem;

namespace clothlab::host {

namespace {

template <class Plugin>
std::string list_ids(const std::vector<Plugin>& plugins) {
  std::string ids;
  for (const Plugin& plugin : plugins) {
    ids += ids.empty() ? "" : ", ";
    ids += plugin.info().id;
  }
  return ids.empty() ? "none" : ids;
}

template <class Plugin>
const Plugin& pick(const std::vector<Plugin>& plugins, const fs::path& path, const char* kind,
                   const std::string& contents) {
  if (plugins.size() == 1) return plugins.front();
  const std::string stem = path.stem().string();
  for (const Plugin& plugin : plugins)
    if (plugin.info().id == stem) return plugin;
  throw PluginLoadError("plugin " + path.string() + " provides " +
                        (plugins.empty()
                             ? std::string("no ") + kind
                             : std::string("several ") + kind + "s and none named " + stem) +
                        " (" + contents + ")");
}

}  // namespace

std::string descriptor_refusal(const clothlab_plugin_descriptor& descriptor) {
  const std::vector<DescriptorFinding> findings = descriptor_findings(descriptor);
  return findings.empty() ? std::string() : describe(findings.front());
}

PluginLibrary PluginLibrary::load(const fs::path& path, std::string_view searched) {
  std::shared_ptr<const LibraryHandle> handle = LibraryHandle::open(path, searched);
  const clothlab_plugin_descriptor* descriptor = handle->descriptor();
  if (descriptor == nullptr)
    throw cannot_load(path, CLOTHLAB_PLUGIN_ENTRY_SYMBOL " returned null", searched);
  if (const std::string refusal = descriptor_refusal(*descriptor); !refusal.empty())
    throw cannot_load(path, refusal, searched);

  PluginLibrary library;
  library.path_ = path;
  library.descriptor_ = descriptor;
  library.handle_ = handle;
  for (uint32_t i = 0; i < descriptor->integrator_count; ++i)
    library.integrators_.emplace_back(handle, path, *descriptor->integrators[i]);
  for (uint32_t i = 0; i < descriptor->scenario_count; ++i)
    library.scenarios_.emplace_back(handle, path, *descriptor->scenarios[i]);
  return library;
}

PluginLibrary PluginLibrary::find(std::string_view argument, const PluginSearchPath& search_path) {
  return load(search_path.resolve(argument), search_path.describe());
}

const IntegratorPlugin& PluginLibrary::integrator() const {
  return pick(integrators_, path_, "integrator",
              "integrators: " + list_ids(integrators_) + "; scenarios: " + list_ids(scenarios_));
}

const ScenarioPlugin& PluginLibrary::scenario() const {
  return pick(scenarios_, path_, "scenario",
              "integrators: " + list_ids(integrators_) + "; scenarios: " + list_ids(scenarios_));
}

LibraryScan scan_libraries(const PluginSearchPath& search_path) {
  LibraryScan scan;
  std::map<std::string, fs::path, std::less<>> owner_of_id;
  for (const fs::path& path : search_path.libraries()) {
    try {
      PluginLibrary library = PluginLibrary::load(path);
      std::vector<std::string_view> ids;
      for (const auto& plugin : library.integrators()) ids.push_back(plugin.info().id);
      for (const auto& plugin : library.scenarios()) ids.push_back(plugin.info().id);
      for (std::string_view id : ids) {
        const auto [it, inserted] = owner_of_id.emplace(std::string(id), path);
        if (!inserted)
          scan.errors.push_back("duplicate plugin id " + std::string(id) + " in " + path.string() +
                                " and " + it->second.string());
      }
      scan.libraries.push_back(std::move(library));
    } catch (const PluginLoadError& error) {
      scan.errors.emplace_back(error.what());
    }
  }
  return scan;
}

}  // namespace clothlab::host
