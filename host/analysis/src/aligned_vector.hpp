// A zeroed, 64-byte aligned array of doubles: the layout clothlab_system callbacks expect.
#pragma once

#include <cstddef>
#include <cstdlib>
#include <memory>
#include <new>

namespace clothlab::analysis::detail {

class AlignedVector {
 public:
  explicit AlignedVector(std::size_t size) : size_(size) {
    constexpr std::size_t kAlignment = 64;
    const std::size_t bytes = ((size * sizeof(double) + kAlignment - 1) / kAlignment) * kAlignment;
    data_.reset(
        static_cast<double*>(std::aligned_alloc(kAlignment, bytes == 0 ? kAlignment : bytes)));
    if (!data_) throw std::bad_alloc();
    for (std::size_t i = 0; i < size; ++i) data_[i] = 0.0;
  }
  double* data() { return data_.get(); }
  const double* data() const { return data_.get(); }
  std::size_t size() const { return size_; }
  double& operator[](std::size_t i) { return data_[i]; }
  double operator[](std::size_t i) const { return data_[i]; }

 private:
  struct Free {
    void operator()(double* p) const { std::free(p); }
  };
  std::size_t size_;
  std::unique_ptr<double[], Free> data_;
};

}  // namespace clothlab::analysis::detail
