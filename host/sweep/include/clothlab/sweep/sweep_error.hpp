// Bad sweep input: a one-line message naming source, key, value and what is allowed.
#pragma once

#include <clothlab/host/errors.hpp>

namespace clothlab::sweep {

// An InputError: the program reports it as bad input (exit code 1).
class SweepError : public host::InputError {
 public:
  using host::InputError::InputError;
};

}  // namespace clothlab::sweep
