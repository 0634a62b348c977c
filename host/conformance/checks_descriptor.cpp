// descriptor.*: the metadata a host relies on before calling anything is well formed (fields,
// ids-unique, params: every finding of the loader's own validator, host::descriptor_findings),
// the declared order and cost are plausible, and the integrator extensions a plugin declares
// (ABI 1.2) are sound; integrators and scenarios answer NULL for every id they do not offer.
#include <clothlab/ext/explicit_scheme.h>
#include <clothlab/ext/integrator_traits.h>

#include <clothlab/core/extension_registry.hpp>
#include <clothlab/host/descriptor_findings.hpp>
#include <clothlab/host/identifiers.hpp>
#include <cmath>
#include <string>

#include "check.hpp"
#include "fixtures.hpp"

namespace clothlab::conformance {
namespace {

using host::DescriptorPart;
using host::quoted;

// The check passes when the one validator of descriptors has no finding for it, and otherwise
// fails with every finding it has.
template <class Belongs>
Verdict no_findings(const clothlab_plugin_descriptor& library, Belongs belongs,
                    std::string measured) {
  std::string reasons;
  for (const host::DescriptorFinding& finding : host::descriptor_findings(library))
    if (belongs(finding)) reasons += (reasons.empty() ? "" : "; ") + host::describe(finding);
  require(reasons.empty(), reasons);
  return {true, std::move(measured)};
}

Verdict component_findings(const clothlab_plugin_descriptor& library, const std::string& id,
                           DescriptorPart part, std::string measured) {
  return no_findings(
      library,
      [&](const host::DescriptorFinding& f) { return f.component == id && f.part == part; },
      std::move(measured));
}

Verdict library_fields(const clothlab_plugin_descriptor& library) {
  return no_findings(
      library,
      [](const host::DescriptorFinding& f) {
        return f.kind == "library" && f.part == DescriptorPart::fields;
      },
      std::to_string(library.integrator_count) + " integrators, " +
          std::to_string(library.scenario_count) + " scenarios");
}

Verdict ids_unique(const clothlab_plugin_descriptor& library) {
  return no_findings(
      library,
      [](const host::DescriptorFinding& f) { return f.part == DescriptorPart::unique_ids; }, "");
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
  const uint32_t known = CLOTHLAB_TRAIT_UNCONDITIONALLY_STABLE | CLOTHLAB_TRAIT_ITERATIVE |
                         CLOTHLAB_TRAIT_RESOLVES_CONTACTS | CLOTHLAB_TRAIT_MOVES_ATTACHMENTS |
                         CLOTHLAB_TRAIT_LOCAL_SOLVES | CLOTHLAB_TRAIT_DRAGS_TOWARDS_REST;
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

// get_extension answers NULL for an id nobody publishes: an unknown name, a published name at
// another revision (a scenario answering "clothlab.colliders/2" with its /1 table), no id.
void require_null_for_unpublished(const void* (*get_extension)(const char*), ExtensionSide side) {
  for (const std::string& id : unpublished_ids(side))
    require(get_extension(id.c_str()) == nullptr,
            "get_extension(" + quoted(id.c_str()) + ") is not NULL");
  require(get_extension(nullptr) == nullptr, "get_extension(NULL) is not NULL");
}

// get_extension answers NULL for what it does not offer, and what it offers is sound.
Verdict integrator_extensions(const clothlab_integrator& integrator) {
  if (!CLOTHLAB_HAS_FIELD(&integrator, clothlab_integrator, get_extension) ||
      integrator.get_extension == nullptr)
    return {true, "none (a struct before ABI 1.2 or no get_extension)"};
  require_null_for_unpublished(integrator.get_extension, ExtensionSide::Integrator);
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

// As for integrators; what a scenario offers is checked by the scenario.* checks.
Verdict scenario_extensions(const clothlab_scenario& scenario) {
  if (!CLOTHLAB_HAS_FIELD(&scenario, clothlab_scenario, get_extension) ||
      scenario.get_extension == nullptr)
    return {true, "none (a struct before ABI 1.3 or no get_extension)"};
  require_null_for_unpublished(scenario.get_extension, ExtensionSide::Scenario);
  std::string offered;
  for (const char* id : published_ids(ExtensionSide::Scenario))
    if (scenario.get_extension(id) != nullptr)
      offered += std::string(offered.empty() ? "" : ", ") + id;
  return {true, offered.empty() ? "none offered" : offered};
}

}  // namespace

std::vector<Check> descriptor_checks(const clothlab_plugin_descriptor& library) {
  const clothlab_plugin_descriptor* lib = &library;
  const auto fields = [lib](std::string id) {
    return [lib, id] { return component_findings(*lib, id, DescriptorPart::fields, ""); };
  };
  const auto params = [lib](std::string id, uint32_t count) {
    return [lib, id, count] {
      return component_findings(*lib, id, DescriptorPart::params,
                                std::to_string(count) + " parameters");
    };
  };
  std::vector<Check> checks = {
      {"library", "descriptor.fields", [lib] { return library_fields(*lib); }},
      {"library", "descriptor.ids-unique", [lib] { return ids_unique(*lib); }},
  };
  for (uint32_t i = 0; i < library.integrator_count && library.integrators != nullptr; ++i) {
    const clothlab_integrator* c = library.integrators[i];
    if (c == nullptr || c->id == nullptr) continue;
    checks.push_back({c->id, "descriptor.fields", fields(c->id)});
    checks.push_back({c->id, "descriptor.order", [c] { return integrator_order(*c); }});
    checks.push_back({c->id, "descriptor.extensions", [c] { return integrator_extensions(*c); }});
    checks.push_back({c->id, "descriptor.params", params(c->id, c->param_count)});
  }
  for (uint32_t i = 0; i < library.scenario_count && library.scenarios != nullptr; ++i) {
    const clothlab_scenario* c = library.scenarios[i];
    if (c == nullptr || c->id == nullptr) continue;
    checks.push_back({c->id, "descriptor.fields", fields(c->id)});
    checks.push_back({c->id, "descriptor.extensions", [c] { return scenario_extensions(*c); }});
    checks.push_back({c->id, "descriptor.params", params(c->id, c->param_count)});
  }
  return checks;
}

}  // namespace clothlab::conformance
