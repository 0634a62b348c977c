#include "plugin_listing.hpp"

#include <clothlab/host/param_text.hpp>
#include <clothlab/host/plugin_library.hpp>

namespace clothlab::cli {

namespace {

void print_params(const host::ComponentInfo& info, const host::ParamSet& defaults,
                  std::ostream& out) {
  if (info.params.empty() && defaults.text_specs().empty()) {
    out << "    parameters: none\n";
    return;
  }
  out << "    parameters:\n";
  for (const clothlab_param_spec& spec : info.params) {
    clothlab_param_value fallback{};
    for (int k = 0; k < 3; ++k) fallback.v[k] = spec.default_value[k];
    out << "      " << info.kind << "." << spec.name << " = "
        << host::format_param_value(spec, fallback) << "  (" << host::describe_allowed(spec)
        << ")  " << spec.help << "\n";
  }
  for (size_t i = 0; i < defaults.text_specs().size(); ++i) {
    const clothlab_text_param_spec& spec = defaults.text_specs()[i];
    out << "      " << info.kind << "." << spec.name << " = \"" << defaults.texts()[i]
        << "\"  (text of at most " << spec.max_length << " bytes"
        << ((spec.flags & CLOTHLAB_TEXT_PATH) != 0 ? ", a file path" : "") << ")  " << spec.help
        << "\n";
  }
}

void print_header(const host::ComponentInfo& info, std::ostream& out) {
  out << "  " << info.kind << " " << info.id << ": " << info.name << ", version " << info.version
      << "\n    " << info.description << "\n";
}

std::string flag_names(const host::IntegratorPlugin& integrator) {
  std::string names;
  if (integrator.uses_velocity_forces()) names += "uses-velocity-forces ";
  const uint32_t unknown = integrator.flags() & ~CLOTHLAB_INTEGRATOR_USES_VELOCITY_FORCES;
  if (unknown != 0) names += "unknown:" + std::to_string(unknown) + " ";
  if (names.empty()) return "none";
  names.pop_back();
  return names;
}

std::string precision_names(const host::IntegratorPlugin& integrator) {
  std::string names;
  if (integrator.supports_precision(CLOTHLAB_FLOAT32)) names += "float32";
  if (integrator.supports_precision(CLOTHLAB_FLOAT64))
    names += names.empty() ? "float64" : " float64";
  return names.empty() ? "none" : names;
}

}  // namespace

int list_plugins(const host::PluginSearchPath& search_path, std::ostream& out,
                 std::ostream& errors) {
  const host::LibraryScan scan = host::scan_libraries(search_path);
  out << "Plugin search path: " << search_path.describe() << "\n";
  if (scan.libraries.empty()) out << "(no plugin libraries found)\n";
  for (const host::PluginLibrary& library : scan.libraries) {
    const clothlab_abi_version abi = library.abi_version();
    out << "\n"
        << library.path().string() << "  (" << library.name() << " " << library.version()
        << ", ABI " << abi.major << "." << abi.minor << ")\n";
    for (const host::IntegratorPlugin& integrator : library.integrators()) {
      const host::ComponentInfo info = integrator.info();
      print_header(info, out);
      out << "    order " << integrator.order() << ", " << integrator.evals_per_step()
          << " force evaluations per step, flags: " << flag_names(integrator)
          << ", precisions: " << precision_names(integrator) << "\n";
      print_params(info, integrator.default_params(), out);
    }
    for (const host::ScenarioPlugin& scenario : library.scenarios()) {
      const host::ComponentInfo info = scenario.info();
      print_header(info, out);
      print_params(info, scenario.default_params(), out);
    }
  }
  for (const std::string& error : scan.errors) errors << "clothlab: error: " << error << "\n";
  return static_cast<int>(scan.errors.size());
}

namespace {

nlohmann::json component_json(const host::ComponentInfo& info) {
  nlohmann::json parameters = nlohmann::json::array();
  for (const clothlab_param_spec& spec : info.params) {
    clothlab_param_value fallback{};
    for (int k = 0; k < 3; ++k) fallback.v[k] = spec.default_value[k];
    parameters.push_back({{"key", std::string(info.kind) + "." + spec.name},
                          {"default", host::format_param_value(spec, fallback)},
                          {"allowed", host::describe_allowed(spec)},
                          {"help", spec.help}});
  }
  return {{"kind", std::string(info.kind)},
          {"id", std::string(info.id)},
          {"name", std::string(info.name)},
          {"version", std::string(info.version)},
          {"description", std::string(info.description)},
          {"parameters", parameters}};
}

}  // namespace

nlohmann::json plugin_listing_json(const host::PluginSearchPath& search_path) {
  const host::LibraryScan scan = host::scan_libraries(search_path);
  nlohmann::json libraries = nlohmann::json::array();
  for (const host::PluginLibrary& library : scan.libraries) {
    const clothlab_abi_version abi = library.abi_version();
    nlohmann::json components = nlohmann::json::array();
    for (const host::IntegratorPlugin& integrator : library.integrators()) {
      nlohmann::json component = component_json(integrator.info());
      component["order"] = integrator.order();
      component["evals_per_step"] = integrator.evals_per_step();
      component["flags"] = flag_names(integrator);
      component["precisions"] = precision_names(integrator);
      components.push_back(std::move(component));
    }
    for (const host::ScenarioPlugin& scenario : library.scenarios())
      components.push_back(component_json(scenario.info()));
    libraries.push_back({{"path", library.path().string()},
                         {"name", std::string(library.name())},
                         {"version", std::string(library.version())},
                         {"abi", std::to_string(abi.major) + "." + std::to_string(abi.minor)},
                         {"components", std::move(components)}});
  }
  return {{"search_path", search_path.describe()},
          {"libraries", std::move(libraries)},
          {"errors", scan.errors}};
}

}  // namespace clothlab::cli
