// --filter: a POSIX extended regular expression searched in "plugin:component check".
#pragma once

#include <regex.h>

#include <string>

namespace clothlab::conformance {

class CheckFilter {
 public:
  // Throws std::invalid_argument with the regex library's message for a bad pattern.
  explicit CheckFilter(const std::string& pattern);
  ~CheckFilter();
  CheckFilter(const CheckFilter&) = delete;
  CheckFilter& operator=(const CheckFilter&) = delete;

  bool matches(const std::string& name) const;

 private:
  regex_t compiled_;
};

}  // namespace clothlab::conformance
