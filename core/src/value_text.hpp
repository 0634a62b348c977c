// A number as the core's validation messages write it: 17 significant digits, so the value
// named is exactly the value refused.
#pragma once

#include <sstream>
#include <string>

namespace clothlab::detail {

inline std::string value_text(double value) {
  std::ostringstream out;
  out.precision(17);
  out << value;
  return out.str();
}

}  // namespace clothlab::detail
