// --list-plugins: every plugin library on the search path, its components, their parameters,
// traits and extensions, built once as data and printed as text for people or as JSON for tools
// (docs/reference/plugin-listing.md).
#pragma once

#include <clothlab/host/plugin_search_path.hpp>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <ostream>
#include <string>
#include <vector>

namespace clothlab::cli {

struct ListedParameter {
  std::string key;            // "integrator.iterations"
  std::string default_value;  // as a --set value would write it
  std::string allowed;        // "integer 1 .. 64"
  std::string help;
};

struct ListedComponent {
  std::string kind;  // "integrator" or "scenario"
  std::string id, name, version, description;
  std::vector<ListedParameter> parameters;
  std::vector<std::string> extensions;  // the published ids it answers (extension registry)
  // Integrators only.
  uint32_t order = 0;
  uint32_t evals_per_step = 0;
  std::vector<std::string> flags;       // "uses-velocity-forces"
  std::vector<std::string> precisions;  // "float32", "float64"
  std::vector<std::string> traits;      // clothlab.integrator-traits/1: "resolves-contacts", ...
};

struct ListedLibrary {
  std::string path, name, version;
  uint32_t abi_major = 0, abi_minor = 0;
  std::vector<ListedComponent> components;
};

struct PluginListing {
  std::string search_path;
  std::vector<ListedLibrary> libraries;
  std::vector<std::string> errors;  // a load error or a duplicate id each
};

PluginListing plugin_listing(const host::PluginSearchPath& search_path);

void print_listing_text(const PluginListing& listing, std::ostream& out);
// One JSON object, schema_version 1 (docs/reference/plugin-listing.md): what
// `--list-plugins --json` prints and the Python module's clothlab.plugins() returns.
nlohmann::json listing_json(const PluginListing& listing);
void print_listing_json(const PluginListing& listing, std::ostream& out);

// Prints the listing to out (text, or JSON when `json`) and each error to errors (one line each,
// "clothlab: error: " prefixed). Returns the number of errors.
int list_plugins(const host::PluginSearchPath& search_path, bool json, std::ostream& out,
                 std::ostream& errors);

}  // namespace clothlab::cli
