// A zeroed, 64-byte aligned array of trivially copyable elements, owned by value.
//
// Large arrays start at staggered offsets within a page. The allocator maps each large array
// afresh at the same page offset, so arrays that one loop walks in step (positions,
// velocities, accelerations) would share their low address bits at every index, which the
// first-level cache's sets and the processor's store-to-load checks look at alone; how fast a
// substep ran then depended on which arrays earlier allocations had left at the same offset.
#pragma once

#include <atomic>
#include <cstddef>
#include <cstdlib>
#include <cstring>
#include <new>
#include <utility>

namespace clothlab::detail {

inline constexpr std::size_t kAlignment = 64;
// Arrays from this size on are staggered, over this many steps of kAlignment (a prime, so
// that arrays allocated one after another get different offsets).
inline constexpr std::size_t kStaggerFromBytes = 16384, kStaggerSteps = 61;

inline std::size_t next_stagger_bytes() {
  static std::atomic<std::size_t> arrays{0};
  return arrays.fetch_add(1, std::memory_order_relaxed) % kStaggerSteps * kAlignment;
}

template <class T>
class AlignedBuffer {
 public:
  AlignedBuffer() = default;
  explicit AlignedBuffer(std::size_t count) : count_(count) {
    if (count == 0) return;
    const std::size_t bytes = (count * sizeof(T) + kAlignment - 1) / kAlignment * kAlignment;
    const std::size_t stagger = bytes >= kStaggerFromBytes ? next_stagger_bytes() : 0;
    block_ = static_cast<std::byte*>(std::aligned_alloc(kAlignment, bytes + stagger));
    if (block_ == nullptr) throw std::bad_alloc();
    data_ = reinterpret_cast<T*>(block_ + stagger);
    std::memset(data_, 0, bytes);
  }
  ~AlignedBuffer() { std::free(block_); }
  AlignedBuffer(AlignedBuffer&& other) noexcept
      : block_(std::exchange(other.block_, nullptr)),
        data_(std::exchange(other.data_, nullptr)),
        count_(std::exchange(other.count_, 0)) {}
  AlignedBuffer& operator=(AlignedBuffer&& other) noexcept {
    std::swap(block_, other.block_);
    std::swap(data_, other.data_);
    std::swap(count_, other.count_);
    return *this;
  }
  AlignedBuffer(const AlignedBuffer&) = delete;
  AlignedBuffer& operator=(const AlignedBuffer&) = delete;

  T* data() { return data_; }
  const T* data() const { return data_; }
  std::size_t size() const { return count_; }
  T& operator[](std::size_t i) { return data_[i]; }
  const T& operator[](std::size_t i) const { return data_[i]; }

 private:
  std::byte* block_ = nullptr;  // what aligned_alloc gave: data_ less the stagger
  T* data_ = nullptr;
  std::size_t count_ = 0;
};

}  // namespace clothlab::detail
