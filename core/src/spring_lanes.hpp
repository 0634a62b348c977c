// A ClothModel's springs laid out once for the lane kernels (float_lanes.hpp, spring_kernel.hpp):
// the general path's spring forces, and any per-spring product summed per particle.
//
// The springs are reordered by the offset between their ends (second - first), then by first
// particle. On a mesh numbered along rows (a grid read from a file, most exported sheets) a
// block of kSpringBlock springs then usually joins consecutive particles to consecutive ones and
// is read with plain loads, as the grid's row kernels read; any other block gathers its ends.
// Each spring writes its own slot, and each particle sums the slots of its springs in one fixed
// order (ascending slot; minus where it is the second end), so any split of the blocks among
// threads gives the same bits, with no atomics.
#pragma once

#include <clothlab/core/cloth_model.hpp>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "aligned_buffer.hpp"
#include "float_lanes.hpp"
#include "simd_namespace.hpp"

namespace clothlab::detail::inline CLOTHLAB_SIMD_NAMESPACE {

#if defined(CLOTHLAB_FLOAT_LANES)
inline constexpr std::size_t kSpringBlock = kLanes;
#else
inline constexpr std::size_t kSpringBlock = 16;
#endif

template <class Real>
class SpringLanes {
 public:
  // damped: keep the springs' kd (false: an integrator that takes no velocity forces).
  SpringLanes(const ClothModel& model, bool damped);

  // Slots: the springs, then padding up to whole blocks (at least one slot, always 0, that
  // particles with fewer springs than their block's widest sum).
  std::size_t slots() const { return first_.size(); }
  std::size_t spring_blocks() const { return slots() / kSpringBlock; }
  std::size_t particle_blocks() const { return row_begin_.size() - 1; }
  uint64_t damped_count() const { return damped_count_; }

  // The force on each spring's first particle (Hooke, plus damping along the spring when v is
  // given), component k of slot s at force[k * slots() + s], for the spring blocks [begin, end).
  // x and v hold component k of particle i at [k * stride + i].
  void forces(const Real* x, const Real* v, std::size_t stride, std::size_t begin, std::size_t end,
              Real* force) const;

  // For the particles of block b (particle b * kSpringBlock + l in lane l): the sum over each
  // particle's springs of per_slot (laid out as forces'), with a minus where it is the second
  // end, into sum[k][l].
  void sum_incident(const Real* per_slot, std::size_t block, Real (&sum)[3][kSpringBlock]) const;

 private:
  static constexpr uint32_t kSecondEnd = 0x80000000u;  // entry flag: subtract this slot

  // What a spring block reads: its lane 0's ends (the others follow in order) or every lane's
  // by index; one law for all lanes, or a law per lane. Only what a block needs is read.
  enum BlockKind : uint8_t { kEndsInOrder = 1, kOneLaw = 2 };
  struct BlockLaw {
    Real rest, ks, kd;
  };

  std::size_t springs_ = 0;
  AlignedBuffer<uint32_t> first_, second_;
  AlignedBuffer<Real> rest_, ks_, kd_;  // kd 0 where the spring is not damped
  std::vector<uint8_t> block_kind_;
  std::vector<uint32_t> block_first_, block_second_;  // per block: its lane 0's ends
  std::vector<BlockLaw> block_law_;                   // per block: lane 0's law
  uint64_t damped_count_ = 0;
  bool damped_ = false;

  // Per particle block, rows [row_begin_[b], row_begin_[b + 1]) of kSpringBlock entries: lane
  // l of row r is the slot (| kSecondEnd) that particle l adds r-th, the zero slot past its
  // springs.
  std::vector<uint32_t> row_begin_;
  AlignedBuffer<uint32_t> entries_;
  std::vector<uint8_t> row_in_order_;  // per row: its lanes are consecutive entries
  std::vector<uint32_t> row_first_;    // per row: its lane 0's entry
};

}  // namespace clothlab::detail::inline CLOTHLAB_SIMD_NAMESPACE
