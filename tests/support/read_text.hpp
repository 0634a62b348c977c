// A file's whole contents as text, for tests that check what a program wrote ("" if it
// cannot be opened: the expectation on the contents then fails and says so).
#pragma once

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace clothlab::testing {

inline std::string read_text(const std::filesystem::path& path) {
  std::ifstream stream(path);
  std::stringstream text;
  text << stream.rdbuf();
  return text.str();
}

}  // namespace clothlab::testing
