#include "check_filter.hpp"

#include <stdexcept>

namespace clothlab::conformance {

CheckFilter::CheckFilter(const std::string& pattern) {
  const int error = regcomp(&compiled_, pattern.c_str(), REG_EXTENDED | REG_NOSUB);
  if (error != 0) {
    char message[256];
    regerror(error, &compiled_, message, sizeof message);
    throw std::invalid_argument(message);
  }
}

CheckFilter::~CheckFilter() { regfree(&compiled_); }

bool CheckFilter::matches(const std::string& name) const {
  return regexec(&compiled_, name.c_str(), 0, nullptr, 0) == 0;
}

}  // namespace clothlab::conformance
