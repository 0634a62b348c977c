#include "plugin_listing.hpp"

#include <clothlab/ext/integrator_traits.h>

#include <clothlab/core/extension_registry.hpp>
#include <clothlab/host/param_text.hpp>
#include <clothlab/host/plugin_library.hpp>
#include <nlohmann/json.hpp>

namespace clothlab::cli {

namespace {

std::vector<ListedParameter> parameters_of(const host::ComponentInfo& info) {
  std::vector<ListedParameter> parameters;
  for (const clothlab_param_spec& spec : info.params) {
    clothlab_param_value fallback{};
    for (int k = 0; k < 3; ++k) fallback.v[k] = spec.default_value[k];
    parameters.push_back({std::string(info.kind) + "." + spec.name,
                          host::format_param_value(spec, fallback), host::describe_allowed(spec),
                          spec.help != nullptr ? spec.help : ""});
  }
  return parameters;
}

template <class Component>
std::vector<std::string> extensions_of(const Component& component, ExtensionSide side) {
  std::vector<std::string> ids;
  for (const char* id : published_ids(side))
    if (component.extension(id) != nullptr) ids.emplace_back(id);
  return ids;
}

std::vector<std::string> flag_names(const host::IntegratorPlugin& integrator) {
  std::vector<std::string> names;
  if (integrator.uses_velocity_forces()) names.emplace_back("uses-velocity-forces");
  const uint32_t unknown = integrator.flags() & ~CLOTHLAB_INTEGRATOR_USES_VELOCITY_FORCES;
  if (unknown != 0) names.push_back("unknown:" + std::to_string(unknown));
  return names;
}

std::vector<std::string> precision_names(const host::IntegratorPlugin& integrator) {
  std::vector<std::string> names;
  if (integrator.supports_precision(CLOTHLAB_FLOAT32)) names.emplace_back("float32");
  if (integrator.supports_precision(CLOTHLAB_FLOAT64)) names.emplace_back("float64");
  return names;
}

std::vector<std::string> trait_names(const host::IntegratorPlugin& integrator) {
  static constexpr std::pair<uint32_t, const char*> known[] = {
      {CLOTHLAB_TRAIT_UNCONDITIONALLY_STABLE, "unconditionally-stable"},
      {CLOTHLAB_TRAIT_ITERATIVE, "iterative"},
      {CLOTHLAB_TRAIT_RESOLVES_CONTACTS, "resolves-contacts"},
      {CLOTHLAB_TRAIT_MOVES_ATTACHMENTS, "moves-attachments"},
      {CLOTHLAB_TRAIT_LOCAL_SOLVES, "local-solves"},
      {CLOTHLAB_TRAIT_DRAGS_TOWARDS_REST, "drags-towards-rest"}};
  const auto* traits = static_cast<const clothlab_integrator_traits*>(
      integrator.extension(CLOTHLAB_EXT_INTEGRATOR_TRAITS));
  std::vector<std::string> names;
  if (traits == nullptr) return names;
  uint32_t unknown = traits->flags;
  for (const auto& [bit, name] : known)
    if (traits->flags & bit) {
      names.emplace_back(name);
      unknown &= ~bit;
    }
  if (unknown != 0) names.push_back("unknown:" + std::to_string(unknown));
  return names;
}

// Text parameters (clothlab.text-parameters/1) follow the numeric ones, listed as --set would
// write them.
void add_text_parameters(const host::ComponentInfo& info, const host::ParamSet& defaults,
                         std::vector<ListedParameter>& parameters) {
  for (size_t i = 0; i < defaults.text_specs().size(); ++i) {
    const clothlab_text_param_spec& spec = defaults.text_specs()[i];
    parameters.push_back({std::string(info.kind) + "." + spec.name,
                          "\"" + defaults.texts()[i] + "\"",
                          "text of at most " + std::to_string(spec.max_length) + " bytes" +
                              ((spec.flags & CLOTHLAB_TEXT_PATH) != 0 ? ", a file path" : ""),
                          spec.help != nullptr ? spec.help : ""});
  }
}

ListedComponent component_of(const host::ComponentInfo& info, const host::ParamSet& defaults) {
  ListedComponent component;
  component.kind = info.kind;
  component.id = info.id;
  component.name = info.name;
  component.version = info.version;
  component.description = info.description;
  component.parameters = parameters_of(info);
  add_text_parameters(info, defaults, component.parameters);
  return component;
}

std::string joined(const std::vector<std::string>& names) {
  if (names.empty()) return "none";
  std::string text;
  for (const std::string& name : names) text += (text.empty() ? "" : " ") + name;
  return text;
}

}  // namespace

PluginListing plugin_listing(const host::PluginSearchPath& search_path) {
  const host::LibraryScan scan = host::scan_libraries(search_path);
  PluginListing listing;
  listing.search_path = search_path.describe();
  for (const host::PluginLibrary& library : scan.libraries) {
    const clothlab_abi_version abi = library.abi_version();
    ListedLibrary& listed = listing.libraries.emplace_back();
    listed.path = library.path().string();
    listed.name = library.name();
    listed.version = library.version();
    listed.abi_major = abi.major;
    listed.abi_minor = abi.minor;
    for (const host::IntegratorPlugin& integrator : library.integrators()) {
      ListedComponent component = component_of(integrator.info(), integrator.default_params());
      component.extensions = extensions_of(integrator, ExtensionSide::Integrator);
      component.order = integrator.order();
      component.evals_per_step = integrator.evals_per_step();
      component.flags = flag_names(integrator);
      component.precisions = precision_names(integrator);
      component.traits = trait_names(integrator);
      listed.components.push_back(std::move(component));
    }
    for (const host::ScenarioPlugin& scenario : library.scenarios()) {
      ListedComponent component = component_of(scenario.info(), scenario.default_params());
      component.extensions = extensions_of(scenario, ExtensionSide::Scenario);
      listed.components.push_back(std::move(component));
    }
  }
  listing.errors = scan.errors;
  return listing;
}

void print_listing_text(const PluginListing& listing, std::ostream& out) {
  out << "Plugin search path: " << listing.search_path << "\n";
  if (listing.libraries.empty()) out << "(no plugin libraries found)\n";
  for (const ListedLibrary& library : listing.libraries) {
    out << "\n"
        << library.path << "  (" << library.name << " " << library.version << ", ABI "
        << library.abi_major << "." << library.abi_minor << ")\n";
    for (const ListedComponent& component : library.components) {
      out << "  " << component.kind << " " << component.id << ": " << component.name << ", version "
          << component.version << "\n    " << component.description << "\n";
      if (component.kind == "integrator")
        out << "    order " << component.order << ", " << component.evals_per_step
            << " force evaluations per step, flags: " << joined(component.flags)
            << ", precisions: " << joined(component.precisions) << "\n"
            << "    traits: " << joined(component.traits) << "\n";
      out << "    extensions: " << joined(component.extensions) << "\n";
      if (component.parameters.empty()) {
        out << "    parameters: none\n";
        continue;
      }
      out << "    parameters:\n";
      for (const ListedParameter& parameter : component.parameters)
        out << "      " << parameter.key << " = " << parameter.default_value << "  ("
            << parameter.allowed << ")  " << parameter.help << "\n";
    }
  }
}

nlohmann::json listing_json(const PluginListing& listing) {
  nlohmann::json libraries = nlohmann::json::array();
  for (const ListedLibrary& library : listing.libraries) {
    nlohmann::json integrators = nlohmann::json::array(), scenarios = nlohmann::json::array();
    for (const ListedComponent& component : library.components) {
      nlohmann::json parameters = nlohmann::json::array();
      for (const ListedParameter& parameter : component.parameters)
        parameters.push_back({{"key", parameter.key},
                              {"default", parameter.default_value},
                              {"allowed", parameter.allowed},
                              {"help", parameter.help}});
      nlohmann::json entry = {{"id", component.id},
                              {"name", component.name},
                              {"version", component.version},
                              {"description", component.description},
                              {"extensions", component.extensions},
                              {"parameters", parameters}};
      if (component.kind == "integrator") {
        entry["order"] = component.order;
        entry["evals_per_step"] = component.evals_per_step;
        entry["flags"] = component.flags;
        entry["precisions"] = component.precisions;
        entry["traits"] = component.traits;
        integrators.push_back(std::move(entry));
      } else {
        scenarios.push_back(std::move(entry));
      }
    }
    libraries.push_back({{"path", library.path},
                         {"name", library.name},
                         {"version", library.version},
                         {"abi", {{"major", library.abi_major}, {"minor", library.abi_minor}}},
                         {"integrators", integrators},
                         {"scenarios", scenarios}});
  }
  return {{"schema_version", 1},
          {"search_path", listing.search_path},
          {"libraries", libraries},
          {"errors", listing.errors}};
}

void print_listing_json(const PluginListing& listing, std::ostream& out) {
  out << listing_json(listing).dump(2) << "\n";
}

int list_plugins(const host::PluginSearchPath& search_path, bool json, std::ostream& out,
                 std::ostream& errors) {
  const PluginListing listing = plugin_listing(search_path);
  if (json)
    print_listing_json(listing, out);
  else
    print_listing_text(listing, out);
  for (const std::string& error : listing.errors) errors << "clothlab: error: " << error << "\n";
  return static_cast<int>(listing.errors.size());
}

}  // namespace clothlab::cli
