// --list-plugins: every plugin library on the search path, its components and parameters.
#pragma once

#include <clothlab/host/plugin_search_path.hpp>
#include <nlohmann/json.hpp>
#include <ostream>

namespace clothlab::cli {

// Prints the listing to out and each load error or duplicate id to errors (one line
// each, "clothlab: error: " prefixed). Returns the number of errors.
int list_plugins(const host::PluginSearchPath& search_path, std::ostream& out,
                 std::ostream& errors);

// The same listing as data: {"search_path", "libraries": [{"path", "name", "version", "abi",
// "components": [{"kind", "id", "name", "version", "description", "parameters": [{"key",
// "default", "allowed", "help"}], and for an integrator "order", "evals_per_step", "flags",
// "precisions"}]}], "errors": [...]}.
nlohmann::json plugin_listing_json(const host::PluginSearchPath& search_path);

}  // namespace clothlab::cli
