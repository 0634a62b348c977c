// Bad sweep input: a one-line message naming source, key, value and what is allowed.
#pragma once

#include <stdexcept>

namespace clothlab::sweep {

class SweepError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace clothlab::sweep
