// Folders of the test plugin libraries built beside these tests.
#pragma once

#include <filesystem>

namespace clothlab::test {

inline std::filesystem::path test_plugin_dir(const char* group) {
  return std::filesystem::path(CLOTHLAB_TEST_PLUGIN_DIR) / group;
}

}  // namespace clothlab::test
