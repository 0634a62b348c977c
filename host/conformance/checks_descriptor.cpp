// descriptor.*: the metadata a host relies on before calling anything is well formed.
#include <clothlab/host/identifiers.hpp>
#include <cmath>
#include <set>
#include <string>

#include "check.hpp"

namespace clothlab::conformance {
namespace {

bool non_empty(const char* text) { return text != nullptr && text[0] != '\0'; }

std::string quoted(const char* text) {
  if (text == nullptr) return "null";
  std::string result(1, '"');
  result += text;
  result += '"';
  return result;
}

void require_strings(const char* id, const char* name, const char* version,
                     const char* description) {
  require(id != nullptr && host::is_plugin_id(id), "id " + quoted(id) + " must match [a-z0-9_-]+");
  require(non_empty(name), "name " + quoted(name) + " is empty");
  require(non_empty(version), "version " + quoted(version) + " is empty");
  require(non_empty(description), "description " + quoted(description) + " is empty");
}

void require_spec(const clothlab_param_spec& spec) {
  const std::string name = spec.name != nullptr ? spec.name : "(null)";
  require(spec.struct_size >= sizeof(clothlab_param_spec),
          name + ": struct_size " + std::to_string(spec.struct_size) + " < " +
              std::to_string(sizeof(clothlab_param_spec)));
  require(spec.name != nullptr && host::is_param_name(spec.name),
          "parameter name " + quoted(spec.name) + " must match [a-z0-9_.]+");
  require(spec.help != nullptr && spec.unit != nullptr, name + ": help or unit is null");
  const bool known = spec.type >= CLOTHLAB_PARAM_REAL && spec.type <= CLOTHLAB_PARAM_VEC3;
  require(known, name + ": unknown type " + std::to_string(spec.type));
  require(std::isfinite(spec.min_value) && std::isfinite(spec.max_value) &&
              spec.min_value <= spec.max_value,
          name + ": range [" + std::to_string(spec.min_value) + ", " +
              std::to_string(spec.max_value) + "] is not a finite interval");
  if (spec.type == CLOTHLAB_PARAM_BOOL)
    require(spec.min_value == 0.0 && spec.max_value == 1.0, name + ": bool range must be [0, 1]");
  const int components = spec.type == CLOTHLAB_PARAM_VEC3 ? 3 : 1;
  for (int k = 0; k < components; ++k) {
    const double value = spec.default_value[k];
    require(std::isfinite(value) && value >= spec.min_value && value <= spec.max_value,
            name + ": default " + std::to_string(value) + " outside [" +
                std::to_string(spec.min_value) + ", " + std::to_string(spec.max_value) + "]");
    if (spec.type == CLOTHLAB_PARAM_INT || spec.type == CLOTHLAB_PARAM_BOOL)
      require(std::floor(value) == value,
              name + ": default " + std::to_string(value) + " is not an integer");
  }
}

Verdict params_consistent(const clothlab_param_spec* specs, uint32_t count) {
  require(count == 0 || specs != nullptr,
          "param_count is " + std::to_string(count) + " but params is null");
  std::set<std::string> names;
  for (uint32_t i = 0; i < count; ++i) {
    require_spec(specs[i]);
    require(names.insert(specs[i].name).second,
            std::string("parameter name \"") + specs[i].name + "\" is declared twice");
  }
  return {true, std::to_string(count) + " parameters"};
}

Verdict library_fields(const clothlab_plugin_descriptor& library) {
  require(library.struct_size >= sizeof(clothlab_plugin_descriptor),
          "struct_size " + std::to_string(library.struct_size) + " < " +
              std::to_string(sizeof(clothlab_plugin_descriptor)));
  require(non_empty(library.library_name), "library_name is empty");
  require(non_empty(library.library_version), "library_version is empty");
  require(library.integrator_count + library.scenario_count > 0, "the library has no components");
  require(library.integrator_count == 0 || library.integrators != nullptr, "integrators is null");
  require(library.scenario_count == 0 || library.scenarios != nullptr, "scenarios is null");
  for (uint32_t i = 0; i < library.integrator_count; ++i)
    require(library.integrators[i] != nullptr, "integrators[" + std::to_string(i) + "] is null");
  for (uint32_t i = 0; i < library.scenario_count; ++i)
    require(library.scenarios[i] != nullptr, "scenarios[" + std::to_string(i) + "] is null");
  return {true, std::to_string(library.integrator_count) + " integrators, " +
                    std::to_string(library.scenario_count) + " scenarios"};
}

Verdict ids_unique(const clothlab_plugin_descriptor& library) {
  std::set<std::string> ids;
  auto insert = [&](const char* id) {
    require(id != nullptr, "a component has a null id");
    require(ids.insert(id).second, std::string("id \"") + id + "\" is used twice");
  };
  for (uint32_t i = 0; i < library.integrator_count; ++i) insert(library.integrators[i]->id);
  for (uint32_t i = 0; i < library.scenario_count; ++i) insert(library.scenarios[i]->id);
  return {true, ""};
}

Verdict integrator_fields(const clothlab_integrator& integrator) {
  require(integrator.struct_size >= sizeof(clothlab_integrator),
          "struct_size " + std::to_string(integrator.struct_size) + " < " +
              std::to_string(sizeof(clothlab_integrator)));
  require_strings(integrator.id, integrator.name, integrator.version, integrator.description);
  require(integrator.create && integrator.prepare && integrator.step && integrator.destroy,
          "a function pointer is null");
  return {true, ""};
}

Verdict integrator_order(const clothlab_integrator& integrator) {
  require(integrator.order >= 1, "declared order " + std::to_string(integrator.order) + " < 1");
  require(integrator.evals_per_step >= 1,
          "evals_per_step " + std::to_string(integrator.evals_per_step) + " < 1");
  const uint32_t known = (1u << CLOTHLAB_FLOAT32) | (1u << CLOTHLAB_FLOAT64);
  require(integrator.precisions != 0 && (integrator.precisions & ~known) == 0,
          "precisions mask " + std::to_string(integrator.precisions) + " has unknown bits or none");
  return {true, "order " + std::to_string(integrator.order)};
}

Verdict scenario_fields(const clothlab_scenario& scenario) {
  require(scenario.struct_size >= sizeof(clothlab_scenario),
          "struct_size " + std::to_string(scenario.struct_size) + " < " +
              std::to_string(sizeof(clothlab_scenario)));
  require_strings(scenario.id, scenario.name, scenario.version, scenario.description);
  require(scenario.create && scenario.describe && scenario.destroy, "a function pointer is null");
  return {true, ""};
}

}  // namespace

std::vector<Check> descriptor_checks(const clothlab_plugin_descriptor& library) {
  const clothlab_plugin_descriptor* lib = &library;
  std::vector<Check> checks = {
      {"library", "descriptor.fields", [lib] { return library_fields(*lib); }},
      {"library", "descriptor.ids-unique", [lib] { return ids_unique(*lib); }},
  };
  for (uint32_t i = 0; i < library.integrator_count && library.integrators != nullptr; ++i) {
    const clothlab_integrator* c = library.integrators[i];
    if (c == nullptr || c->id == nullptr) continue;
    checks.push_back({c->id, "descriptor.fields", [c] { return integrator_fields(*c); }});
    checks.push_back({c->id, "descriptor.order", [c] { return integrator_order(*c); }});
    checks.push_back(
        {c->id, "descriptor.params", [c] { return params_consistent(c->params, c->param_count); }});
  }
  for (uint32_t i = 0; i < library.scenario_count && library.scenarios != nullptr; ++i) {
    const clothlab_scenario* c = library.scenarios[i];
    if (c == nullptr || c->id == nullptr) continue;
    checks.push_back({c->id, "descriptor.fields", [c] { return scenario_fields(*c); }});
    checks.push_back(
        {c->id, "descriptor.params", [c] { return params_consistent(c->params, c->param_count); }});
  }
  return checks;
}

}  // namespace clothlab::conformance
