// Reads a YAML config file into settings. Nested maps flatten to dotted keys, so
//   scenario: {plugin: flag, structural: {ks: 50}}
// gives scenario.plugin = flag and scenario.structural.ks = 50, the same keys as --set.
// A sequence of scalars becomes "[a, b, c]" (a vec3). Each setting's source is
// "file:line:column" of its value.
#pragma once

#include <filesystem>
#include <vector>

#include "settings.hpp"

namespace clothlab::cli {

// Throws InputError for an unreadable file, a YAML syntax error, a non-map document, an
// empty value or a sequence that is not of scalars.
std::vector<Setting> read_config_file(const std::filesystem::path& path);

}  // namespace clothlab::cli
