// A ClothModel's springs laid out once for the lane kernels (float_lanes.hpp, spring_kernel.hpp):
// the general path's spring forces, and any per-spring product summed per particle.
//
// The springs that share an offset between their ends (second - first) form a band where they
// cover at least a fifth of a range of first particles: the band gives every first particle of its
// range a slot, in order, the slots without a spring left dead (they give 0). A band's block then
// joins consecutive particles to consecutive ones and is read with plain loads, as the grid's row
// kernels read, and each particle block sums a band's slots with one plain load per end. On a
// mesh numbered along rows (a grid read from a file, a sheet generated row by row) nearly every
// spring lies in a band; the others follow, ordered by offset and first particle, and are gathered.
// Each spring writes its own slot, and each particle sums the slots of its springs in one fixed
// order (the bands', then its gathered slots ascending; minus where it is the second end), so
// any split of the blocks among threads gives the same bits, with no atomics.
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

  // Slots: a dead block, each band followed by a dead block, then the gathered springs padded
  // to whole blocks. Slot 0 (always 0) is what particles with fewer gathered springs than their
  // block's widest sum.
  std::size_t slots() const { return first_.size(); }
  std::size_t spring_blocks() const { return slots() / kSpringBlock; }
  std::size_t particle_blocks() const { return row_begin_.size() - 1; }
  uint64_t damped_count() const { return damped_count_; }
  // The model's spring in slot s; spring_count() where the slot is dead.
  uint32_t spring_in(std::size_t slot) const { return spring_in_[slot]; }

  // The force on each spring's first particle (Hooke, plus damping along the spring when v is
  // given), component k of slot s at force[k * slots() + s], for the spring blocks [begin, end).
  // x and v hold component k of particle i at [k * stride + i].
  void forces(const Real* x, const Real* v, std::size_t stride, std::size_t begin, std::size_t end,
              Real* force) const;

  // M_s (u_second - u_first) of each slot s, the ends with inverse mass 0 taken as u = 0, with
  // M_s symmetric, its coefficients (xx, xy, xz, yy, yz, zz) q at matrix[q * slots() + s]; laid
  // out as forces', for the spring blocks [begin, end).
  void symmetric_products(const Real* matrix, const Real* u, const Real* inverse_mass,
                          std::size_t stride, std::size_t begin, std::size_t end,
                          Real* product) const;

  // For the particles of block b (particle b * kSpringBlock + l in lane l): the sum over each
  // particle's springs of per_slot (laid out as forces'), with a minus where it is the second
  // end, into sum[k][l].
  void sum_incident(const Real* per_slot, std::size_t block, Real (&sum)[3][kSpringBlock]) const;

 private:
  static constexpr uint32_t kSecondEnd = 0x80000000u;  // entry flag: subtract this slot

  // What a spring block reads: its lane 0's ends (the others follow in order) or every lane's
  // by index; one law for all lanes, or a law per lane. Only what a block needs is read.
  // A block with dead slots writes 0 there; a block with no spring writes only 0.
  enum BlockKind : uint8_t { kEndsInOrder = 1, kOneLaw = 2, kDeadSlots = 4, kNoSpring = 8 };
  struct BlockLaw {
    Real rest, ks, kd;
  };

  std::size_t springs_ = 0;
  AlignedBuffer<uint32_t> first_, second_;
  // kd 0 where the spring is not damped; a dead slot's law is 0 (ks + kd = 0 says it is dead).
  AlignedBuffer<Real> rest_, ks_, kd_;
  std::vector<uint32_t> spring_in_;  // per slot: the model's spring (springs_: dead)
  std::vector<uint8_t> block_kind_;
  std::vector<uint32_t> block_first_, block_second_;  // per block: its lane 0's ends
  std::vector<BlockLaw> block_law_;                   // per block: lane 0's law
  uint64_t damped_count_ = 0;
  bool damped_ = false;

  // Per particle block, rows [row_begin_[b], row_begin_[b + 1]) of kSpringBlock entries: lane
  // l of row r is the slot (| kSecondEnd) that particle l adds r-th (a band's row: the slots of
  // consecutive first, or second, particles), slot 0 past its gathered springs.
  std::vector<uint32_t> row_begin_;
  AlignedBuffer<uint32_t> entries_;
  std::vector<uint8_t> row_in_order_;  // per row: its lanes are consecutive entries
  std::vector<uint32_t> row_first_;    // per row: its lane 0's entry
};

}  // namespace clothlab::detail::inline CLOTHLAB_SIMD_NAMESPACE
