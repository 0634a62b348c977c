// A named conformance check and the settings every check may read.
#pragma once

#include <clothlab/plugin.h>

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "verdict.hpp"

namespace clothlab::conformance {

struct Check {
  std::string component;  // "library", or an integrator or scenario id
  std::string name;       // "<group>.<check>", e.g. "numerics.order-spring"
  std::function<Verdict()> body;
  // A check that runs a whole cloth for seconds (stability.*) gets this multiple of the
  // runner's --timeout.
  double timeout_scale = 1.0;
};

using Values = std::vector<clothlab_param_value>;

// What the parameter checks need from a component of either kind.
struct ParameterSubject {
  std::string component;
  const clothlab_param_spec* specs = nullptr;
  uint32_t count = 0;
  // Calls create, destroys any instance it made, returns the status (message filled).
  std::function<clothlab_status(const Values&, clothlab_message&)> try_create;
  // Creates an instance from valid values and uses it; fails the check on a bad result.
  std::function<void(const Values&)> exercise;
};

struct Settings {
  uint64_t seed = 1;
};

// One family of checks per file; each returns the checks for one library or component.
std::vector<Check> loading_checks(const std::string& path);
std::vector<Check> descriptor_checks(const clothlab_plugin_descriptor& library);
std::vector<Check> parameter_checks(const ParameterSubject& subject, const Settings& settings);
std::vector<Check> lifecycle_checks(const clothlab_integrator& integrator);
std::vector<Check> numerics_checks(const clothlab_integrator& integrator);
// Only for an integrator declaring CLOTHLAB_TRAIT_MOVES_ATTACHMENTS.
std::vector<Check> attachment_checks(const clothlab_integrator& integrator);
std::vector<Check> robustness_checks(const clothlab_integrator& integrator);
std::vector<Check> stability_checks(const clothlab_integrator& integrator);
std::vector<Check> contacts_checks(const clothlab_integrator& integrator);
std::vector<Check> scenario_checks(const clothlab_scenario& scenario);

}  // namespace clothlab::conformance
