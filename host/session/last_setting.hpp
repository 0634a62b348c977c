// Where a key was set: the last of its settings, for errors found after parsing.
#pragma once

#include <string>
#include <vector>

#include "settings.hpp"

namespace clothlab::cli {

// The last setting of `key`, or nullptr.
const Setting* last_setting(const std::vector<Setting>& settings, const std::string& key);
// "file.yaml:3:5: key" where the last setting of `key` was written, or the key alone when its
// default stands: the prefix of an error found after parsing.
std::string where_set(const std::vector<Setting>& settings, const std::string& key);

}  // namespace clothlab::cli
