// Checks run after every step. A check that fails stops the run as unstable; more checks
// (spring stretch, energy growth) plug in beside the non-finite one.
#pragma once

#include <clothlab/core/cloth.hpp>
#include <cstdint>
#include <optional>
#include <string>

namespace clothlab::cli {

class StepObserver {
 public:
  virtual ~StepObserver() = default;
  // Called after step `step` (1-based) completed; returns the verdict if the state is
  // unacceptable and the run must stop.
  virtual std::optional<std::string> after_step(const Cloth& cloth, uint64_t step) = 0;
};

// Fails at the first step that leaves a NaN or infinity in the positions or velocities.
class FiniteStateCheck final : public StepObserver {
 public:
  std::optional<std::string> after_step(const Cloth& cloth, uint64_t step) override {
    if (cloth.state_is_finite()) return std::nullopt;
    return "non-finite state at step " + std::to_string(step);
  }
};

}  // namespace clothlab::cli
