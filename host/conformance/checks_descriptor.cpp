// descriptor.*: the metadata a host relies on before calling anything is well formed, and
// the integrator extensions a plugin declares (ABI 1.2) are sound.
#include <clothlab/ext/explicit_scheme.h>
#include <clothlab/ext/integrator_traits.h>
#include <clothlab/host/identifiers.hpp>

#include <cmath>
#include <set>
#include <string>

#include "check.hpp"
#include "fixtures.hpp"

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
  require(spec.struct_size >= CLOTHLAB_PARAM_SPEC_SIZE_1_0,
          name + ": struct_size " + std::to_string(spec.struct_size) + " < " +
              std::to_string(CLOTHLAB_PARAM_SPEC_SIZE_1_0) + " (ABI 1.0)");
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
  require(library.struct_size >= CLOTHLAB_DESCRIPTOR_SIZE_1_0,
          "struct_size " + std::to_string(library.struct_size) + " < " +
              std::to_string(CLOTHLAB_DESCRIPTOR_SIZE_1_0) + " (ABI 1.0)");
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
  require(integrator.struct_size >= CLOTHLAB_INTEGRATOR_SIZE_1_0,
          "struct_size " + std::to_string(integrator.struct_size) + " < " +
              std::to_string(CLOTHLAB_INTEGRATOR_SIZE_1_0) + " (ABI 1.0)");
  require_strings(integrator.id, integrator.name, integrator.version, integrator.description);
  require(integrator.create && integrator.prepare && integrator.step && integrator.destroy,
          "a function pointer is null");
  return {true, ""};
}

Verdict integrator_order(const clothlab_integrator& integrator) {
  require(integrator.order >= 1, "declared order " + std::to_string(integrator.order) + " < 1");
  // An iterative method's cost is set by its substep and iteration parameters; it may call
  // eval_acceleration not at all (XPBD projects the springs itself).
  require(integrator.evals_per_step >= 1 || has_trait(integrator, CLOTHLAB_TRAIT_ITERATIVE),
          "evals_per_step " + std::to_string(integrator.evals_per_step) +
              " < 1 (0 only for an integrator declaring CLOTHLAB_TRAIT_ITERATIVE)");
  const uint32_t known = (1u << CLOTHLAB_FLOAT32) | (1u << CLOTHLAB_FLOAT64);
  require(integrator.precisions != 0 && (integrator.precisions & ~known) == 0,
          "precisions mask " + std::to_string(integrator.precisions) + " has unknown bits or none");
  return {true, "order " + std::to_string(integrator.order)};
}

bool names_integer_parameter(const clothlab_integrator& integrator, const char* name) {
  for (uint32_t i = 0; i < integrator.param_count; ++i)
    if (std::string(integrator.params[i].name) == name &&
        integrator.params[i].type == CLOTHLAB_PARAM_INT)
      return true;
  return false;
}

void require_traits(const clothlab_integrator& integrator, const clothlab_integrator_traits& t) {
  require(t.struct_size >= sizeof(clothlab_integrator_traits),
          "traits struct_size " + std::to_string(t.struct_size) + " < " +
              std::to_string(sizeof(clothlab_integrator_traits)));
  const uint32_t known = CLOTHLAB_TRAIT_UNCONDITIONALLY_STABLE | CLOTHLAB_TRAIT_ITERATIVE;
  require((t.flags & ~known) == 0, "traits flags " + std::to_string(t.flags) + " has unknown bits");
  for (const char* name : {t.substeps_param, t.iterations_param})
    require(name == nullptr || names_integer_parameter(integrator, name),
            std::string("traits name parameter ") + quoted(name) +
                ", which is not an integer parameter of the integrator");
  // The order checks raise an iterative method's iteration count: they must know its name.
  require((t.flags & CLOTHLAB_TRAIT_ITERATIVE) == 0 || t.iterations_param != nullptr,
          "CLOTHLAB_TRAIT_ITERATIVE without iterations_param");
}

// The table is well formed and costs what the descriptor declares.
void require_scheme(const clothlab_integrator& integrator, const clothlab_explicit_scheme& e) {
  require(e.struct_size >= sizeof(clothlab_explicit_scheme),
          "explicit scheme struct_size " + std::to_string(e.struct_size) + " < " +
              std::to_string(sizeof(clothlab_explicit_scheme)));
  require(e.first_same_as_last <= 1, "first_same_as_last must be 0 or 1");
  require(e.scheme != nullptr, "the explicit scheme has no table");
  const clothlab_rkn_scheme& table = *e.scheme;
  require(table.struct_size >= sizeof(clothlab_rkn_scheme) && table.stages >= 1 &&
              table.stages <= CLOTHLAB_RKN_MAX_STAGES,
          "the table has struct_size " + std::to_string(table.struct_size) + " and " +
              std::to_string(table.stages) + " stages (allowed 1 .. " +
              std::to_string(CLOTHLAB_RKN_MAX_STAGES) + ")");
  const uint32_t s = table.stages;
  for (const auto& [array, count] : {std::pair{table.c, s},
                                     {table.alpha, s},
                                     {table.x_coupling, s * s},
                                     {table.v_coupling, s * s},
                                     {table.x_weights, s},
                                     {table.v_weights, s}}) {
    require(array != nullptr, "the table has a null array");
    for (uint32_t i = 0; i < count; ++i)
      require(std::isfinite(array[i]), "the table has a non-finite entry");
  }
  const uint32_t evaluations = s - (e.first_same_as_last != 0 && s > 1 ? 1 : 0);
  require(evaluations == integrator.evals_per_step,
          "the declared scheme takes " + std::to_string(evaluations) +
              " evaluations per step, the descriptor says evals_per_step = " +
              std::to_string(integrator.evals_per_step));
}

// get_extension answers NULL for what it does not offer, and what it offers is sound.
Verdict integrator_extensions(const clothlab_integrator& integrator) {
  if (!CLOTHLAB_HAS_FIELD(&integrator, clothlab_integrator, get_extension) ||
      integrator.get_extension == nullptr)
    return {true, "none (a struct before ABI 1.2 or no get_extension)"};
  for (const char* id : {"clothlab.no-such-extension/1", "", "clothlab.integrator-traits/2",
                         "clothlab.explicit-scheme/0", "clothlab.explicit-scheme"})
    require(integrator.get_extension(id) == nullptr,
            std::string("get_extension(") + quoted(id) + ") is not NULL");
  require(integrator.get_extension(nullptr) == nullptr, "get_extension(NULL) is not NULL");
  std::string offered;
  if (const void* traits = integrator.get_extension(CLOTHLAB_EXT_INTEGRATOR_TRAITS)) {
    require_traits(integrator, *static_cast<const clothlab_integrator_traits*>(traits));
    offered += CLOTHLAB_EXT_INTEGRATOR_TRAITS;
  }
  if (const void* scheme = integrator.get_extension(CLOTHLAB_EXT_EXPLICIT_SCHEME)) {
    require_scheme(integrator, *static_cast<const clothlab_explicit_scheme*>(scheme));
    offered += std::string(offered.empty() ? "" : ", ") + CLOTHLAB_EXT_EXPLICIT_SCHEME;
  }
  return {true, offered.empty() ? "none offered" : offered};
}

Verdict scenario_fields(const clothlab_scenario& scenario) {
  require(scenario.struct_size >= CLOTHLAB_SCENARIO_SIZE_1_0,
          "struct_size " + std::to_string(scenario.struct_size) + " < " +
              std::to_string(CLOTHLAB_SCENARIO_SIZE_1_0) + " (ABI 1.0)");
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
    checks.push_back({c->id, "descriptor.extensions", [c] { return integrator_extensions(*c); }});
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
