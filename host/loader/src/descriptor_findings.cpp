#include "clothlab/host/descriptor_findings.hpp"

#include <cmath>
#include <optional>
#include <set>
#include <string>
#include <utility>

#include "clothlab/host/errors.hpp"
#include "clothlab/host/identifiers.hpp"
#include "clothlab/host/param_text.hpp"

namespace clothlab::host {

namespace {

// "[1, 64]", appended piece by piece: GCC 12 warns falsely on "[" + std::string.
std::string interval_text(double low, double high) {
  std::string text(1, '[');
  text += format_number(low);
  text += ", ";
  text += format_number(high);
  return text += ']';
}

std::string at_least(size_t size) { return "at least " + std::to_string(size) + " (ABI 1.0)"; }

// Where findings go and whose they are: the library, or one integrator or scenario.
class Owner {
 public:
  Owner(std::vector<DescriptorFinding>& findings, std::string kind, std::string component,
        std::string prefix = {})
      : findings_(findings),
        kind_(std::move(kind)),
        component_(std::move(component)),
        prefix_(std::move(prefix)) {}

  void add(DescriptorPart part, const std::string& field, std::string value, std::string allowed) {
    findings_.push_back(
        {part, component_, kind_, prefix_ + field, std::move(value), std::move(allowed)});
  }
  void require_text(const char* field, const char* text) {
    if (text == nullptr || *text == '\0')
      add(DescriptorPart::fields, field, quoted(text), "a non-empty string");
  }
  void require_function(const char* field, bool present) {
    if (!present) add(DescriptorPart::fields, field, "null", "a function");
  }

 private:
  std::vector<DescriptorFinding>& findings_;
  std::string kind_, component_, prefix_;
};

// The spec's default as written, component by component (a bool's 0.5 stays 0.5).
std::string default_text(const clothlab_param_spec& spec) {
  if (spec.type != CLOTHLAB_PARAM_VEC3) return format_number(spec.default_value[0]);
  clothlab_param_value value{};
  for (int k = 0; k < 3; ++k) value.v[k] = spec.default_value[k];
  return format_param_value(spec, value);
}

bool default_allowed(const clothlab_param_spec& spec) {
  const bool whole = spec.type == CLOTHLAB_PARAM_INT || spec.type == CLOTHLAB_PARAM_BOOL;
  for (int k = 0; k < (spec.type == CLOTHLAB_PARAM_VEC3 ? 3 : 1); ++k) {
    const double value = spec.default_value[k];
    if (!(std::isfinite(value) && value >= spec.min_value && value <= spec.max_value)) return false;
    if (whole && std::floor(value) != value) return false;
  }
  return true;
}

void check_spec(Owner& owner, const clothlab_param_spec& spec, uint32_t index,
                std::set<std::string>& names) {
  constexpr auto part = DescriptorPart::params;
  const std::string at = "params[" + std::to_string(index) + "]";
  if (spec.struct_size < CLOTHLAB_PARAM_SPEC_SIZE_1_0) {
    owner.add(part, at + ".struct_size", std::to_string(spec.struct_size),
              at_least(CLOTHLAB_PARAM_SPEC_SIZE_1_0));
    return;
  }
  const bool named = spec.name != nullptr && is_param_name(spec.name);
  if (!named) owner.add(part, at + ".name", quoted(spec.name), "[a-z0-9_.]+");
  const std::string field = named ? "params." + std::string(spec.name) : at;
  if (named && !names.insert(spec.name).second)
    owner.add(part, field + ".name", quoted(spec.name),
              "a name no other parameter of the component has");
  if (spec.help == nullptr) owner.add(part, field + ".help", "null", "a string");
  if (spec.unit == nullptr) owner.add(part, field + ".unit", "null", "a string");
  if (spec.type < CLOTHLAB_PARAM_REAL || spec.type > CLOTHLAB_PARAM_VEC3) {
    owner.add(part, field + ".type", std::to_string(spec.type), "real, int, bool or vec3");
    return;
  }
  const std::string range = interval_text(spec.min_value, spec.max_value);
  if (!std::isfinite(spec.min_value) || !std::isfinite(spec.max_value) ||
      spec.min_value > spec.max_value) {
    owner.add(part, field + ".range", range, "a finite [min, max] with min <= max");
    return;
  }
  if (spec.type == CLOTHLAB_PARAM_BOOL && (spec.min_value != 0.0 || spec.max_value != 1.0)) {
    owner.add(part, field + ".range", range, "[0, 1] for a bool");
    return;
  }
  if (!default_allowed(spec))
    owner.add(part, field + ".default_value", default_text(spec), describe_allowed(spec));
}

void check_params(Owner& owner, const clothlab_param_spec* params, uint32_t count) {
  if (count > 0 && params == nullptr) {
    owner.add(DescriptorPart::params, "params", "null",
              "an array of param_count = " + std::to_string(count) + " specs");
    return;
  }
  std::set<std::string> names;
  for (uint32_t i = 0; i < count; ++i) check_spec(owner, params[i], i, names);
}

// The owner of a component's findings: the component named by its id, or the library when the
// id cannot name it.
Owner component_owner(std::vector<DescriptorFinding>& findings, const char* kind,
                      const std::string& entry, const char* id) {
  if (id == nullptr) return {findings, "library", "library", entry + "."};
  return {findings, kind, id};
}

// Checks what integrators and scenarios share; returns the component's owner, or nothing when the
// struct is too short to read further.
template <class Component>
std::optional<Owner> check_common(std::vector<DescriptorFinding>& findings, const char* kind,
                                  const std::string& entry, const Component& component,
                                  size_t minimum_size, std::set<std::string>& ids) {
  // The id lies where every published layout has it, so even a short struct is named by it.
  Owner owner = component_owner(findings, kind, entry, component.id);
  if (component.struct_size < minimum_size) {
    owner.add(DescriptorPart::fields, "struct_size", std::to_string(component.struct_size),
              at_least(minimum_size));
    return std::nullopt;
  }
  if (component.id == nullptr || !is_plugin_id(component.id))
    owner.add(DescriptorPart::fields, "id", quoted(component.id), "[a-z0-9_-]+");
  else if (!ids.insert(component.id).second)
    owner.add(DescriptorPart::unique_ids, "id", quoted(component.id),
              "an id no other component of the library has");
  owner.require_text("name", component.name);
  owner.require_text("version", component.version);
  owner.require_text("description", component.description);
  return owner;
}

void check_integrator(std::vector<DescriptorFinding>& findings, uint32_t index,
                      const clothlab_integrator& c, std::set<std::string>& ids) {
  std::optional<Owner> owner =
      check_common(findings, "integrator", "integrators[" + std::to_string(index) + "]", c,
                   CLOTHLAB_INTEGRATOR_SIZE_1_0, ids);
  if (!owner) return;
  owner->require_function("create", c.create != nullptr);
  owner->require_function("prepare", c.prepare != nullptr);
  owner->require_function("step", c.step != nullptr);
  owner->require_function("destroy", c.destroy != nullptr);
  check_params(*owner, c.params, c.param_count);
}

void check_scenario(std::vector<DescriptorFinding>& findings, uint32_t index,
                    const clothlab_scenario& c, std::set<std::string>& ids) {
  std::optional<Owner> owner =
      check_common(findings, "scenario", "scenarios[" + std::to_string(index) + "]", c,
                   CLOTHLAB_SCENARIO_SIZE_1_0, ids);
  if (!owner) return;
  owner->require_function("create", c.create != nullptr);
  owner->require_function("describe", c.describe != nullptr);
  owner->require_function("destroy", c.destroy != nullptr);
  check_params(*owner, c.params, c.param_count);
}

}  // namespace

std::string describe(const DescriptorFinding& finding) {
  const std::string owner =
      finding.kind == "library" ? finding.kind : finding.kind + " " + finding.component;
  return one_line(owner + ": " + finding.field + " = " + finding.value + ", allowed " +
                  finding.allowed);
}

std::string abi_version_text(const clothlab_abi_version& version) {
  return std::to_string(version.major) + "." + std::to_string(version.minor);
}

std::vector<DescriptorFinding> descriptor_findings(const clothlab_plugin_descriptor& descriptor) {
  std::vector<DescriptorFinding> findings;
  Owner library(findings, "library", "library");
  if (!clothlab_abi_is_compatible(descriptor.abi_version)) {
    library.add(DescriptorPart::fields, "abi_version", abi_version_text(descriptor.abi_version),
                std::to_string(CLOTHLAB_ABI_VERSION_MAJOR) + ".x (host ABI version " +
                    abi_version_text({CLOTHLAB_ABI_VERSION_MAJOR, CLOTHLAB_ABI_VERSION_MINOR}) +
                    ")");
    return findings;
  }
  if (descriptor.struct_size < CLOTHLAB_DESCRIPTOR_SIZE_1_0) {
    library.add(DescriptorPart::fields, "struct_size", std::to_string(descriptor.struct_size),
                at_least(CLOTHLAB_DESCRIPTOR_SIZE_1_0));
    return findings;
  }
  library.require_text("library_name", descriptor.library_name);
  library.require_text("library_version", descriptor.library_version);
  if (descriptor.integrator_count == 0 && descriptor.scenario_count == 0)
    library.add(DescriptorPart::fields, "integrator_count + scenario_count", "0",
                "at least 1 (a library provides a component)");
  std::set<std::string> ids;
  if (descriptor.integrator_count > 0 && descriptor.integrators == nullptr)
    library.add(DescriptorPart::fields, "integrators", "null",
                "an array of integrator_count = " + std::to_string(descriptor.integrator_count) +
                    " pointers");
  else
    for (uint32_t i = 0; i < descriptor.integrator_count; ++i)
      if (descriptor.integrators[i] == nullptr)
        library.add(DescriptorPart::fields, "integrators[" + std::to_string(i) + "]", "null",
                    "an integrator");
      else
        check_integrator(findings, i, *descriptor.integrators[i], ids);
  if (descriptor.scenario_count > 0 && descriptor.scenarios == nullptr)
    library.add(
        DescriptorPart::fields, "scenarios", "null",
        "an array of scenario_count = " + std::to_string(descriptor.scenario_count) + " pointers");
  else
    for (uint32_t i = 0; i < descriptor.scenario_count; ++i)
      if (descriptor.scenarios[i] == nullptr)
        library.add(DescriptorPart::fields, "scenarios[" + std::to_string(i) + "]", "null",
                    "a scenario");
      else
        check_scenario(findings, i, *descriptor.scenarios[i], ids);
  return findings;
}

}  // namespace clothlab::host
