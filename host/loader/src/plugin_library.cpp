#include "clothlab/host/plugin_library.hpp"

#include <dlfcn.h>

#include <boost/dll/shared_library.hpp>
#include <map>
#include <set>

#include "clothlab/host/errors.hpp"
#include "clothlab/host/identifiers.hpp"
#include "clothlab/host/param_text.hpp"

namespace fs = std::filesystem;

namespace clothlab::host {

struct LibraryHandle {
  boost::dll::shared_library library;
};

namespace {

// Boost.DLL clears dlerror(), so ask the dynamic loader again for its reason.
std::string dlopen_reason(const fs::path& path) {
  void* handle = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (handle == nullptr) {
    const char* reason = dlerror();
    std::string text = reason ? reason : "unknown dlopen failure";
    // dlerror starts with the path, which the caller's message already names.
    const std::string prefix = path.string() + ": ";
    if (text.starts_with(prefix)) text.erase(0, prefix.size());
    return text;
  }
  dlclose(handle);
  return "Boost.DLL could not open it";
}

// Checks the parts common to integrators and scenarios; returns the problem or "".
std::string component_problem(const char* kind, uint32_t index, uint32_t struct_size,
                              size_t host_size, const char* id,
                              std::initializer_list<const char*> strings,
                              std::initializer_list<bool> functions,
                              const clothlab_param_spec* params, uint32_t param_count) {
  const std::string where = std::string(kind) + " #" + std::to_string(index);
  if (struct_size < host_size)
    return where + " has struct_size " + std::to_string(struct_size) + ", host needs at least " +
           std::to_string(host_size);
  if (id == nullptr || !is_plugin_id(id))
    return where + " has id \"" + (id ? id : "(null)") + "\", expected [a-z0-9_-]+";
  const std::string named = std::string(kind) + " " + id;
  for (const char* text : strings)
    if (text == nullptr) return named + " has a null name, version or description";
  for (bool present : functions)
    if (!present) return named + " has a null function pointer";
  if (param_count > 0 && params == nullptr) return named + " has a null parameter array";
  std::set<std::string_view> names;
  for (uint32_t i = 0; i < param_count; ++i) {
    if (const auto problem = spec_problem(params[i])) return named + ": " + *problem;
    if (!names.insert(params[i].name).second)
      return named + " declares parameter " + params[i].name + " twice";
  }
  return {};
}

std::string descriptor_problem(const clothlab_plugin_descriptor& descriptor) {
  if (descriptor.struct_size < sizeof(clothlab_plugin_descriptor))
    return "descriptor struct_size " + std::to_string(descriptor.struct_size) +
           " is smaller than the " + std::to_string(sizeof(clothlab_plugin_descriptor)) +
           " bytes this host reads";
  if (descriptor.library_name == nullptr || descriptor.library_version == nullptr)
    return "descriptor has a null library name or version";
  if ((descriptor.integrator_count > 0 && descriptor.integrators == nullptr) ||
      (descriptor.scenario_count > 0 && descriptor.scenarios == nullptr))
    return "descriptor has a null component list";
  std::set<std::string_view> ids;
  for (uint32_t i = 0; i < descriptor.integrator_count; ++i) {
    const clothlab_integrator* c = descriptor.integrators[i];
    if (c == nullptr) return "integrator #" + std::to_string(i) + " is null";
    const std::string problem = component_problem(
        "integrator", i, c->struct_size, sizeof(clothlab_integrator), c->id,
        {c->name, c->version, c->description},
        {c->create != nullptr, c->prepare != nullptr, c->step != nullptr, c->destroy != nullptr},
        c->params, c->param_count);
    if (!problem.empty()) return problem;
    if (!ids.insert(c->id).second) return std::string("duplicate component id ") + c->id;
  }
  for (uint32_t i = 0; i < descriptor.scenario_count; ++i) {
    const clothlab_scenario* c = descriptor.scenarios[i];
    if (c == nullptr) return "scenario #" + std::to_string(i) + " is null";
    const std::string problem =
        component_problem("scenario", i, c->struct_size, sizeof(clothlab_scenario), c->id,
                          {c->name, c->version, c->description},
                          {c->create != nullptr, c->describe != nullptr, c->destroy != nullptr},
                          c->params, c->param_count);
    if (!problem.empty()) return problem;
    if (!ids.insert(c->id).second) return std::string("duplicate component id ") + c->id;
  }
  return {};
}

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

std::string abi_refusal(const clothlab_abi_version& version) {
  if (version.major == CLOTHLAB_ABI_VERSION_MAJOR) return {};
  return "plugin ABI version " + std::to_string(version.major) + "." +
         std::to_string(version.minor) + " is incompatible with host ABI version " +
         std::to_string(CLOTHLAB_ABI_VERSION_MAJOR) + "." +
         std::to_string(CLOTHLAB_ABI_VERSION_MINOR) + " (major versions differ)";
}

std::string descriptor_refusal(const clothlab_plugin_descriptor& descriptor) {
  // The version comes first and is checked before any other field is read.
  if (std::string refusal = abi_refusal(descriptor.abi_version); !refusal.empty()) return refusal;
  return descriptor_problem(descriptor);
}

PluginLibrary PluginLibrary::load(const fs::path& path, std::string_view searched) {
  const std::string suffix =
      searched.empty() ? std::string() : " (plugin search path: " + std::string(searched) + ")";
  const auto fail = [&](const std::string& why) -> PluginLoadError {
    return PluginLoadError("cannot load plugin " + path.string() + ": " + why + suffix);
  };

  std::error_code exists_error;
  if (!fs::exists(path, exists_error)) throw fail("no such file");

  auto handle = std::make_shared<LibraryHandle>();
  boost::dll::fs::error_code error;
  handle->library.load(path, error, boost::dll::load_mode::rtld_now);
  if (error || !handle->library.is_loaded())
    throw fail("not a loadable shared library: " + dlopen_reason(path));
  if (!handle->library.has(CLOTHLAB_PLUGIN_ENTRY_SYMBOL))
    throw fail("no entry symbol " CLOTHLAB_PLUGIN_ENTRY_SYMBOL " (not a ClothLab plugin)");

  const auto& entry =
      handle->library.get<const clothlab_plugin_descriptor*()>(CLOTHLAB_PLUGIN_ENTRY_SYMBOL);
  const clothlab_plugin_descriptor* descriptor = entry();
  if (descriptor == nullptr) throw fail(CLOTHLAB_PLUGIN_ENTRY_SYMBOL " returned null");
  if (const std::string problem = descriptor_refusal(*descriptor); !problem.empty())
    throw fail(problem);

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
