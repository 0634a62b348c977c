// The one YAML reader and flattener. Nested maps flatten to dotted keys, so
//   scenario: {plugin: flag, structural: {ks: 50}}
// gives scenario.plugin = flag and scenario.structural.ks = 50, the same keys as --set.
// A sequence of scalars becomes "[a, b, c]". Each setting's source is "file:line:column" of
// its value. Input is bounded: a regular file of at most 1 MiB, one document (a map; a blank
// or comment-only file sets nothing), at most 100 000 values after aliases are expanded (a
// 702-byte alias bomb expands to billions).
#pragma once

#include <yaml-cpp/yaml.h>

#include <filesystem>
#include <string>
#include <vector>

#include "clothlab/config/setting.hpp"

namespace clothlab::config {

// "file:line:column" (1-based) of a node, or the file alone when the node has no position.
std::string location(const std::string& source, const YAML::Mark& mark);

// Reads and parses one YAML document (a null node when the text holds none). Throws InputError
// naming the path for a missing, unreadable or oversized file, a folder, FIFO or device, a
// syntax error, or a second document.
YAML::Node load_yaml_file(const std::filesystem::path& path);
YAML::Node load_yaml_text(const std::string& text, const std::string& source);

// A map key as plain text; throws InputError at its position for a complex or empty key.
std::string key_text(const YAML::Node& key, const std::string& source);

// Every value of a map document as settings, in file order. Throws InputError at the value's
// position for a key given twice (also spelled differently: a.b and a: {b}), an empty value
// or map, a list that holds more than plain values, or too many values.
std::vector<Setting> flatten_settings(const YAML::Node& root, const std::string& source);

// load_yaml_file + flatten_settings + check_one_length: a single-run config file.
std::vector<Setting> read_config_file(const std::filesystem::path& path);

}  // namespace clothlab::config
