// The outcome of one conformance check.
#pragma once

#include <stdexcept>
#include <string>

namespace clothlab::conformance {

struct Verdict {
  bool passed = false;
  std::string reason;  // why it failed, or what was measured when it passed
};

// Thrown by a check body to fail with a reason; the harness turns it into a Verdict.
class CheckFailure : public std::runtime_error {
 public:
  explicit CheckFailure(const std::string& reason) : std::runtime_error(reason) {}
};

// Fails the running check with `reason` unless `condition` holds.
inline void require(bool condition, const std::string& reason) {
  if (!condition) throw CheckFailure(reason);
}

}  // namespace clothlab::conformance
