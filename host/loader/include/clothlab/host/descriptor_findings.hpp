// The one validator of plugin descriptors: every field of a descriptor that is wrong, each as a
// finding. The loader refuses a library on its first finding; the conformance runner reports
// them all.
#pragma once

#include <clothlab/plugin.h>

#include <string>
#include <vector>

namespace clothlab::host {

// Which conformance check a finding belongs to.
enum class DescriptorPart {
  fields,      // the library's or a component's own fields
  unique_ids,  // an id another component of the library already has
  params,      // a parameter spec of a component
};

struct DescriptorFinding {
  DescriptorPart part = DescriptorPart::fields;
  // "library", or the id of the integrator or scenario the field belongs to. A component whose
  // id cannot be read is the library's: its fields are named "integrators[2].step".
  std::string component;
  std::string kind;     // "library", "integrator" or "scenario"
  std::string field;    // "struct_size", "id", "params.substeps.default_value"
  std::string value;    // as found: "0", "null", "\"SymplecticEuler\""
  std::string allowed;  // "int, a whole number in [1, 64]", "[a-z0-9_-]+"
};

// "integrator euler: params.substeps.default_value = 0, allowed int, a whole number in [1, 64]",
// on one line whatever the plugin's strings hold.
std::string describe(const DescriptorFinding& finding);

// "1.2".
std::string abi_version_text(const clothlab_abi_version& version);

// Every finding, in the order of the descriptor's fields; empty when the descriptor is sound. The
// version comes first: a library of another major is read no further, nor is a struct whose
// struct_size is below ABI 1.0's.
std::vector<DescriptorFinding> descriptor_findings(const clothlab_plugin_descriptor& descriptor);

}  // namespace clothlab::host
