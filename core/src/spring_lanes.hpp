// A ClothModel's springs laid out once for the lane kernels (float_lanes.hpp, spring_kernel.hpp):
// the general path's spring forces, and any per-spring product summed per particle.
//
// The springs that share an offset between their ends (second - first) form a band where they
// cover at least a fifth of a range of first particles: the band gives every first particle of its
// range a slot, in order, the slots without a spring left dead (they give 0). Triangles are laid
// out alike (LaneBands), by the offsets of their other two corners from their smallest. A band's
// block then joins consecutive particles to consecutive ones and is read with plain loads, as the
// grid's row kernels read, and each particle block sums a band's slots with one plain load per end.
// On a mesh numbered along rows (a grid read from a file, a sheet generated row by row) nearly
// every spring lies in a band; the others follow, ordered by offset and first particle, and are
// gathered. Each spring writes its own slot, and each particle sums the slots of its springs in one
// fixed order (the bands', then its gathered slots ascending; minus where it is the second end), so
// any split of the blocks among threads gives the same bits, with no atomics.
//
// sweep() runs the two passes tile by tile, so that a tile's sums read the slots computed just
// before them from cache rather than from memory.
#pragma once

#include <omp.h>

#include <algorithm>
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

// The slots and sums of items with two or three ends (springs, triangles), in the layout the
// head of this file describes: an item's ends are given smallest first, and the items whose other
// ends lie at the same offsets from it form a band.
class LaneBands {
 public:
  // ends: `arity` (2 or 3) particles per item, the smallest first; subtracted: bit e set where
  // end e sums its items' slots with a minus.
  LaneBands(std::size_t particles, const std::vector<uint32_t>& ends, std::size_t arity,
            uint32_t subtracted);

  std::size_t slots() const { return item_in_.size(); }
  std::size_t slot_blocks() const { return slots() / kSpringBlock; }
  std::size_t particle_blocks() const { return row_begin_.size() - 1; }
  std::size_t items() const { return items_; }
  // The item in slot s; items() where the slot is dead.
  uint32_t item_in(std::size_t slot) const { return item_in_[slot]; }
  // End e of each slot (a dead slot's: particles of its band where they exist, else 0).
  const uint32_t* ends(std::size_t e) const { return ends_[e].data(); }
  // Every end of the block's slots follows lane 0's in order.
  bool ends_in_order(std::size_t block) const { return in_order_[block] != 0; }

  // For the particles of block b (particle b * kSpringBlock + l in lane l): adds the sum over
  // each particle's items of per_slot (component k of slot s at per_slot[k * slots() + s]), with
  // a minus where its end is subtracted, to sum[k][l].
  template <class Real>
  void sum_incident(const Real* per_slot, std::size_t block, Real (&sum)[3][kSpringBlock]) const;

  // Calls compute(begin, end) on slot blocks, each once, and sum(tile, begin, end) on the
  // particle blocks of each tile of `tile` blocks, after the slot blocks its sums read. Each
  // thread takes whole tiles in order and computes a band's blocks tile by tile, just before the
  // tile's sums; first, the blocks other threads read (the gathered and dead blocks, and the
  // band blocks within an offset of its last tile), then a barrier. With `also` (a layout of
  // the same particles), its slot blocks likewise by also_compute, before the sums that read them.
  // After the barrier, a tile's slot blocks read (as ends) only the particles of that tile and of
  // the thread's later tiles, so sum may rewrite the state of its tile's particles.
  template <class Compute, class Sum, class AlsoCompute = Compute>
  void sweep(std::size_t tile, int threads, bool parallel, const Compute& compute, const Sum& sum,
             const LaneBands* also = nullptr, const AlsoCompute* also_compute = nullptr) const;

 private:
  static constexpr uint32_t kSubtract = 0x80000000u;  // entry flag: subtract this slot

  // A band: the items of one set of offsets, the largest `reach`, first ends [low, high) (whole
  // blocks) in the slots from base (a whole block).
  struct Band {
    uint32_t reach, low, high;
    std::size_t base;
  };
  // The band's slot blocks whose first ends lie in particle blocks [begin, end).
  template <class Compute>
  static void band_blocks(const Band& band, std::size_t begin, std::size_t end,
                          const Compute& compute);

  std::size_t items_ = 0;
  std::vector<Band> bands_;
  std::vector<uint32_t> dead_blocks_;  // the leading block and the one after each band
  std::size_t gathered_block_ = 0;     // the first gathered slot block
  std::vector<AlignedBuffer<uint32_t>> ends_;
  std::vector<uint32_t> item_in_;
  std::vector<uint8_t> in_order_;  // per slot block

  // Per particle block, rows [row_begin_[b], row_begin_[b + 1]) of kSpringBlock entries: lane
  // l of row r is the slot (| kSubtract) that particle l adds r-th (a band's row: the slots of
  // consecutive particles as one of the band's ends), slot 0 past its gathered items.
  std::vector<uint32_t> row_begin_;
  AlignedBuffer<uint32_t> entries_;
  std::vector<uint8_t> row_in_order_;  // per row: its lanes are consecutive entries
  std::vector<uint32_t> row_first_;    // per row: its lane 0's entry
};

template <class Real>
class SpringLanes {
 public:
  // damped: keep the springs' kd (false: an integrator that takes no velocity forces).
  SpringLanes(const ClothModel& model, bool damped);

  // Slots (LaneBands): a dead block, each band followed by a dead block, then the gathered
  // springs padded to whole blocks. Slot 0 (always 0) is what particles with fewer gathered
  // springs than their block's widest sum.
  std::size_t slots() const { return layout_.slots(); }
  std::size_t spring_blocks() const { return layout_.slot_blocks(); }
  std::size_t particle_blocks() const { return layout_.particle_blocks(); }
  uint64_t damped_count() const { return damped_count_; }
  // The model's spring in slot s; spring_count() where the slot is dead.
  uint32_t spring_in(std::size_t slot) const { return layout_.item_in(slot); }

  // The force on each spring's first particle (Hooke, plus damping along the spring when v is
  // given), component k of slot s at force[k * slots() + s], for the spring blocks [begin, end).
  // x and v hold component k of particle i at [k * stride + i].
  void forces(const Real* x, const Real* v, std::size_t stride, std::size_t begin, std::size_t end,
              Real* force) const;

  // 1/l of each slot's spring at x (0 for a dead slot or a spring of zero length), what the
  // definite products take, for the spring blocks [begin, end).
  void inverse_lengths(const Real* x, std::size_t stride, std::size_t begin, std::size_t end,
                       Real* inverse_length) const;

  // The definite Jacobian's product on each slot s, M_s (u_second - u_first), the ends with
  // inverse mass 0 taken as u = 0: M_s = c_x ks (t I + (1 - t) n n^T) + c_v kd n n^T at x, n the
  // spring's direction, t = max(0, 1 - rest / l), from its 1/l (definite_coefficients, as the
  // grid's kernel: one stored float per spring, not six coefficients, as the products stream
  // memory); laid out as forces', for the spring blocks [begin, end).
  void definite_products(const Real* x, const Real* inverse_length, Real c_x, Real c_v,
                         const Real* u, const Real* inverse_mass, std::size_t stride,
                         std::size_t begin, std::size_t end, Real* product) const;

  // For the particles of block b (particle b * kSpringBlock + l in lane l): the sum over each
  // particle's springs of per_slot (laid out as forces'), with a minus where it is the second
  // end, into sum[k][l].
  void sum_incident(const Real* per_slot, std::size_t block, Real (&sum)[3][kSpringBlock]) const {
    for (std::size_t k = 0; k < 3; ++k) std::fill(sum[k], sum[k] + kSpringBlock, Real(0));
    layout_.sum_incident(per_slot, block, sum);
  }

  // LaneBands::sweep on the springs' slots (and also's).
  template <class Compute, class Sum, class AlsoCompute = Compute>
  void sweep(std::size_t tile, int threads, bool parallel, const Compute& compute, const Sum& sum,
             const LaneBands* also = nullptr, const AlsoCompute* also_compute = nullptr) const {
    layout_.sweep(tile, threads, parallel, compute, sum, also, also_compute);
  }

 private:
  // What a spring block reads: its lane 0's ends (the others follow in order) or every lane's
  // by index; one law for all its live lanes, one ks and kd with a rest length per lane (an
  // irregular mesh's springs of one family), or a law per lane. Only what a block needs is
  // read. A block with dead slots writes 0 there; a block with no spring writes only 0.
  enum BlockKind : uint8_t {
    kEndsInOrder = 1,
    kOneLaw = 2,
    kDeadSlots = 4,
    kNoSpring = 8,
    kOneStiffness = 16
  };
  struct BlockLaw {
    Real rest, ks, kd;
  };

  LaneBands layout_;
  const uint32_t* first_;
  const uint32_t* second_;
  // kd 0 where the spring is not damped; a dead slot's law is 0 (ks + kd = 0 says it is dead).
  AlignedBuffer<Real> rest_, ks_, kd_;
  std::vector<uint8_t> block_kind_;
  std::vector<uint32_t> block_first_, block_second_;  // per block: its lane 0's ends
  std::vector<BlockLaw> block_law_;                   // per block: its first live lane's law
  std::vector<uint32_t> block_live_;                  // per block: bit l set where lane l lives
  uint64_t damped_count_ = 0;
  bool damped_ = false;
};

template <class Compute>
void LaneBands::band_blocks(const Band& band, std::size_t begin, std::size_t end,
                            const Compute& compute) {
  begin = std::max<std::size_t>(begin, band.low / kSpringBlock);
  end = std::min<std::size_t>(end, band.high / kSpringBlock);
  if (begin >= end) return;
  const std::size_t from = band.base / kSpringBlock + (begin - band.low / kSpringBlock);
  compute(from, from + (end - begin));
}

template <class Compute, class Sum, class AlsoCompute>
void LaneBands::sweep(std::size_t tile, int threads, bool parallel, const Compute& compute,
                      const Sum& sum, const LaneBands* also,
                      const AlsoCompute* also_compute) const {
  const std::size_t blocks = particle_blocks();
  const std::size_t tiles = (blocks + tile - 1) / tile;
#pragma omp parallel num_threads(threads) if (parallel)
  {
    const auto count = static_cast<std::size_t>(omp_get_num_threads());
    const auto thread = static_cast<std::size_t>(omp_get_thread_num());
    const std::size_t first_tile = tiles * thread / count;
    const std::size_t last_tile = tiles * (thread + 1) / count;
    const std::size_t begin = std::min(blocks, first_tile * tile);
    const std::size_t end = std::min(blocks, last_tile * tile);
    // A later thread's sums read the first ends of a band's slots up to its reach back.
    const auto shared_from = [&](const Band& band) {
      const std::size_t reach = (band.reach + kSpringBlock - 1) / kSpringBlock;
      return end == blocks ? end : std::max(begin, end - std::min(end, reach));
    };
    const auto shared = [&](const LaneBands& layout, const auto& layout_compute) {
      for (std::size_t k = thread; k < layout.dead_blocks_.size(); k += count)
        layout_compute(std::size_t{layout.dead_blocks_[k]},
                       std::size_t{layout.dead_blocks_[k]} + 1);
      const std::size_t gathered = layout.slot_blocks() - layout.gathered_block_;
      layout_compute(layout.gathered_block_ + gathered * thread / count,
                     layout.gathered_block_ + gathered * (thread + 1) / count);
      for (const Band& band : layout.bands_)
        band_blocks(band, shared_from(band), end, layout_compute);
    };
    const auto in_tile = [&](const LaneBands& layout, const auto& layout_compute,
                             std::size_t tile_begin, std::size_t tile_end) {
      for (const Band& band : layout.bands_)
        band_blocks(band, tile_begin, std::min(tile_end, shared_from(band)), layout_compute);
    };
    shared(*this, compute);
    if (also != nullptr) shared(*also, *also_compute);
#pragma omp barrier
    for (std::size_t t = first_tile; t < last_tile; ++t) {
      const std::size_t tile_begin = t * tile, tile_end = std::min(blocks, tile_begin + tile);
      in_tile(*this, compute, tile_begin, tile_end);
      if (also != nullptr) in_tile(*also, *also_compute, tile_begin, tile_end);
      sum(t, tile_begin, tile_end);
    }
  }
}

}  // namespace clothlab::detail::inline CLOTHLAB_SIMD_NAMESPACE
