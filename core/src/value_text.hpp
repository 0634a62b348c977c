// A number as the core's validation messages write it: 17 significant digits, so the value
// named is exactly the value refused.
#pragma once

#include <array>
#include <charconv>
#include <sstream>
#include <string>

namespace clothlab::detail {

inline std::string value_text(double value) {
  std::ostringstream out;
  out.precision(17);
  out << value;
  return out.str();
}

// The shortest text that reads back as `value` (times and distances in messages about a path).
inline std::string shortest_text(double value) {
  std::array<char, 32> buffer{};
  const auto result = std::to_chars(buffer.data(), buffer.data() + buffer.size(), value);
  return std::string(buffer.data(), result.ptr);
}

}  // namespace clothlab::detail
