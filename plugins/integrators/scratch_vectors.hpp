// Scratch vectors an integrator borrows from the host in `prepare` and reuses in every
// `step`, so stepping never allocates. Remembers which system they belong to, so a step
// on a system the instance was not prepared for is an error rather than a stray write.
#pragma once

#include <array>
#include <clothlab/sdk.hpp>
#include <cstddef>

namespace clothlab::builtin {

template <std::size_t Count>
class ScratchVectors {
 public:
  template <class Real>
  void allocate(const sdk::System<Real>& system) {
    for (void*& vector : vectors_) vector = system.alloc_vector();
    owner_ = system.raw().context;
    precision_ = system.raw().precision;
  }

  template <class Real>
  std::array<Real*, Count> bind(const sdk::System<Real>& system) const {
    if (owner_ == nullptr || owner_ != system.raw().context || precision_ != system.raw().precision)
      throw sdk::Error(CLOTHLAB_ERROR_INVALID_ARGUMENT,
                       "step called on a system the integrator was not prepared for");
    std::array<Real*, Count> typed{};
    for (std::size_t i = 0; i < Count; ++i) typed[i] = static_cast<Real*>(vectors_[i]);
    return typed;
  }

 private:
  std::array<void*, Count> vectors_{};
  const void* owner_ = nullptr;
  uint32_t precision_ = 0;
};

}  // namespace clothlab::builtin
