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
// Two triangles that share an edge form a quad; on a mesh numbered along rows its corners lie at
// p, p + u, p + w and p + u + w. Where an irregular mesh's springs across such quads (the flexion
// across an edge, whose corners vary from quad to quad) would fill several offsets' bands a
// quarter or half each, a chosen band gives each quad's anchor p one slot: its spring joins two of
// the four corners, chosen per lane, so a block loads the four corners in order and picks each
// lane's two ends by mask, and each particle block sums the band with one masked load per corner.
// An irregular mesh's cells, split along one diagonal or the other, give their triangles two
// chosen bands the same way (each triangle three of its cell's four corners).
//
// sweep() runs the two passes tile by tile. After its barrier each thread computes its bands'
// slots into a ring of its own, a tile and a band's reach long per band, and its sums read them
// there: they stay in cache and are never written to the whole-cloth buffer. The slots other
// threads read (gathered, dead, and those near a thread's last tile) are computed before the
// barrier into the whole-cloth buffer, and copied into the ring where its sums read them.
#pragma once

#include <omp.h>

#include <algorithm>
#include <array>
#include <clothlab/core/cloth_model.hpp>
#include <cstddef>
#include <cstdint>
#include <type_traits>
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

// Where a sweep's slots go: full, per component slots() apart, the whole cloth's; rings, each
// thread's ring (LaneBands::ring_slots() per component), thread t's from t * 3 * ring_slots().
template <class Real>
struct SlotBuffers {
  Real* full;
  Real* rings;
};

// A chosen block's ends in the few bytes a block reads (LaneBands::chosen_lanes): per end e and
// lane l the corner (0 to 3, ascending) that is lane l's end e, bit l of low[e] its low bit and of
// high[e] its high bit (lanes_of_bits reads them from memory), and its band, whose corners lie at
// chosen_corners()[band] from the block's first slot.
template <std::size_t Ends>
struct ChosenLanes {
  using Bits = std::conditional_t<(kSpringBlock <= 8), uint8_t, uint16_t>;
  Bits low[Ends] = {}, high[Ends] = {};
  uint16_t band = 0;
};

#if defined(CLOTHLAB_FLOAT_LANES)
// values at end e of a chosen block's lanes, from the values at its corners.
inline Floats chosen_end(const Floats (&corner)[4], LaneMask low, LaneMask high) {
  return select(high, select(low, corner[3], corner[2]), select(low, corner[1], corner[0]));
}
#endif

// The slots and sums of items with two or three ends (springs, triangles), in the layout the
// head of this file describes: an item's ends are given smallest first, and the items whose other
// ends lie at the same offsets from it form a band.
class LaneBands {
 public:
  // ends: `arity` (2 or 3) particles per item, the smallest first; subtracted: bit e set where
  // end e sums its items' slots with a minus; tile: the particle blocks of sweep's tiles.
  LaneBands(std::size_t particles, const std::vector<uint32_t>& ends, std::size_t arity,
            uint32_t subtracted, std::size_t tile);

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
  // Whether the block lies in a chosen band (head of this file) whose corners are all particles;
  // if so, its ends (Ends at least the items' ends): lane l's item has its ends among lane 0's
  // corners + l, lane 0's corner c particle block * kSpringBlock + chosen_corners()[lanes.band][c],
  // modulo 2^32.
  template <std::size_t Ends>
  bool chosen_lanes(std::size_t block, ChosenLanes<Ends>& lanes) const;
  const std::array<uint32_t, 4>* chosen_corners() const { return chosen_corners_.data(); }

  // A thread's ring, per component (SlotBuffers).
  std::size_t ring_slots() const { return ring_slots_; }

  // For the particles of block b (particle b * kSpringBlock + l in lane l): adds the sum over
  // each particle's items of per_slot (component k of slot s at per_slot[k * slots() + s]), with
  // a minus where its end is subtracted, to sum[k][l]. With ring (a thread's ring in a sweep's
  // sum), the bands' slots are read there instead.
  template <class Real>
  void sum_incident(const Real* per_slot, const Real* ring, std::size_t block,
                    Real (&sum)[3][kSpringBlock]) const;

  // Calls compute(begin, end, out, out_stride) on slot blocks, each once (component k of slot
  // begin * kSpringBlock + i to out[k * out_stride + i]), and sum(tile, begin, end, ring,
  // also_ring) on the particle blocks of each tile, after the slot blocks its sums read. Each
  // thread takes whole tiles in order. First it computes into slots.full the blocks other
  // threads read (the gathered and dead blocks, and the band blocks within a band's reach of
  // its last tile), then a barrier; then, tile by tile, it computes its other band blocks into
  // its ring (and copies there those its sums read from slots.full) just before the tile's sums,
  // which read the bands' slots from the ring (sum_incident with ring). With `also` (a layout of
  // the same particles and tile), its slot blocks likewise by also_compute into also_slots.
  // After the barrier, a tile's slot blocks read (as ends) only the particles of that tile and of
  // the thread's later tiles, so sum may rewrite the state of its tile's particles.
  template <class Real, class Compute, class Sum, class AlsoCompute = Compute>
  void sweep(int threads, bool parallel, const SlotBuffers<Real>& slots, const Compute& compute,
             const Sum& sum, const LaneBands* also = nullptr,
             const SlotBuffers<Real>* also_slots = nullptr,
             const AlsoCompute* also_compute = nullptr) const;

 private:
  static constexpr uint32_t kSubtract = 0x80000000u;  // entry flag: subtract this slot

  static constexpr uint32_t kGatheredRow = 0xffffffffu;  // row_ring_: not a band's row

  // A band: the items of one set of offsets, the largest `reach`, first ends [low, high) (whole
  // blocks) in the slots from base (a whole block); in a ring, the slots of first ends p at
  // ring_base + p mod (ring_blocks * kSpringBlock), its first block repeated after them, so a
  // row of consecutive slots never wraps.
  // A chosen band's slot for first end p (its anchor) joins two of p + corner[k].
  struct Band {
    uint32_t reach, low, high;
    std::size_t base;
    std::size_t ring_base = 0, ring_blocks = 0;
    bool chosen = false;
    std::array<uint32_t, 4> corner{};
  };
  // The band's slot blocks whose first ends lie in particle blocks [begin, end).
  template <class Compute>
  static void band_blocks(const Band& band, std::size_t begin, std::size_t end,
                          const Compute& compute);
  // Into a thread's ring, the band's blocks of first ends in particle blocks [from, to): those
  // in [compute_from, compute_to) computed, the others copied from full, and the dead blocks
  // either side of the band 0.
  template <class Real, class Compute>
  void fill_ring(const Band& band, const Real* full, Real* ring, std::ptrdiff_t from,
                 std::ptrdiff_t to, std::ptrdiff_t compute_from, std::ptrdiff_t compute_to,
                 const Compute& compute) const;

  std::size_t items_ = 0;
  std::size_t tile_ = 1;
  uint32_t subtracted_ = 0;  // bit e set where end e subtracts (the constructor's)
  std::size_t ring_slots_ = 0;
  std::vector<Band> bands_;
  std::vector<uint32_t> dead_blocks_;  // the leading block and the one after each band
  std::size_t gathered_block_ = 0;     // the first gathered slot block
  std::vector<AlignedBuffer<uint32_t>> ends_;
  std::vector<uint32_t> item_in_;
  std::vector<uint8_t> in_order_;    // per slot block
  std::vector<uint8_t> corner_of_;   // per slot of a chosen band: end e's corner << 2 e
  std::vector<uint16_t> chosen_of_;  // per slot block: 1 + its chosen band where loadable, else 0
  // Per band: a chosen band's corners less its first slot, band.low - band.base + corner[c]
  // modulo 2^32 (chosen_lanes).
  std::vector<std::array<uint32_t, 4>> chosen_corners_;

  // Per particle block, rows [row_begin_[b], row_begin_[b + 1]) of kSpringBlock entries: lane
  // l of row r is the slot (| kSubtract) that particle l adds r-th (a band's row: the slots of
  // consecutive particles as one of the band's ends), slot 0 past its gathered items.
  std::vector<uint32_t> row_begin_;
  // Per particle block: its first chosen band's row and its first gathered row (its plain bands'
  // rows come first, then the chosen bands', then the gathered: bands_ holds the chosen last).
  std::vector<uint32_t> row_chosen_, row_gathered_;
  AlignedBuffer<uint32_t> entries_;
  std::vector<uint8_t> row_in_order_;  // per row: its lanes are consecutive entries
  std::vector<uint32_t> row_first_;    // per row: its lane 0's entry
  std::vector<uint32_t> row_ring_;     // per row: its lane 0's ring slot (| kSubtract)
  // Per row: none, or for a chosen band's row, bit l of live set where lane l takes its slot and
  // of subtracts where it subtracts it (the other lanes take nothing; lanes_of_bits reads them
  // from memory); its slots then run from row_first_ (and row_ring_) in order.
  struct RowChoice {
    ChosenLanes<1>::Bits live = 0, subtracts = 0;
    bool any() const { return live != 0; }
  };
  std::vector<RowChoice> row_choice_;
};

template <class Real>
class SpringLanes {
 public:
  // damped: keep the springs' kd (false: an integrator that takes no velocity forces); tile:
  // the particle blocks of sweep's tiles.
  SpringLanes(const ClothModel& model, bool damped, std::size_t tile);

  // Slots (LaneBands): a dead block, each band followed by a dead block, then the gathered
  // springs padded to whole blocks. Slot 0 (always 0) is what particles with fewer gathered
  // springs than their block's widest sum.
  std::size_t slots() const { return layout_.slots(); }
  std::size_t spring_blocks() const { return layout_.slot_blocks(); }
  std::size_t particle_blocks() const { return layout_.particle_blocks(); }
  std::size_t ring_slots() const { return layout_.ring_slots(); }
  uint64_t damped_count() const { return damped_count_; }
  // The model's spring in slot s; spring_count() where the slot is dead.
  uint32_t spring_in(std::size_t slot) const { return layout_.item_in(slot); }

  // The force on each spring's first particle (Hooke, plus damping along the spring when v is
  // given), for the spring blocks [begin, end): component k of slot begin * kSpringBlock + i at
  // force[k * force_stride + i]. x and v hold component k of particle i at [k * stride + i].
  void forces(const Real* x, const Real* v, std::size_t stride, std::size_t begin, std::size_t end,
              Real* force, std::size_t force_stride) const;

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
                         std::size_t begin, std::size_t end, Real* product,
                         std::size_t product_stride) const;

  // For the particles of block b (particle b * kSpringBlock + l in lane l): the sum over each
  // particle's springs of per_slot (component k of slot s at per_slot[k * slots() + s]; with
  // ring, a sweep's, the bands' slots from there), with a minus where it is the second end,
  // into sum[k][l].
  void sum_incident(const Real* per_slot, const Real* ring, std::size_t block,
                    Real (&sum)[3][kSpringBlock]) const {
    for (std::size_t k = 0; k < 3; ++k) std::fill(sum[k], sum[k] + kSpringBlock, Real(0));
    layout_.sum_incident(per_slot, ring, block, sum);
  }

  // LaneBands::sweep on the springs' slots (and also's).
  template <class Compute, class Sum, class AlsoCompute = Compute>
  void sweep(int threads, bool parallel, const SlotBuffers<Real>& slots, const Compute& compute,
             const Sum& sum, const LaneBands* also = nullptr,
             const SlotBuffers<Real>* also_slots = nullptr,
             const AlsoCompute* also_compute = nullptr) const {
    layout_.sweep(threads, parallel, slots, compute, sum, also, also_slots, also_compute);
  }

 private:
  // What a spring block reads: its lane 0's ends (the others follow in order), a chosen band's
  // four corners in order (each lane's two ends picked by mask), or every lane's by index; one law
  // for all its live lanes, one ks and kd with a rest length per lane (an irregular mesh's springs
  // of one family), two ks and kd picked per lane by mask with a rest length per lane (a band that
  // mixes two families, as an irregular mesh's diagonals: shear and flexion), or a law per lane.
  // Only what a block needs is read. A block with dead slots writes 0 there; a block with no
  // spring writes only 0. A run of blocks of one kind reads its first block's ends in order (the
  // others follow, kSpringBlock apart) and, unless chosen, its one law or one stiffness: a block
  // whose own do not follow its predecessor's flips kRunParity, so it starts a run.
  enum BlockKind : uint8_t {
    kEndsInOrder = 1,
    kOneLaw = 2,
    kDeadSlots = 4,
    kNoSpring = 8,
    kOneStiffness = 16,
    kChosen = 32,
    kTwoStiffnesses = 64,
    kRunParity = 128
  };
  struct BlockLaw {
    Real rest, ks, kd;
  };
  // For each block b of [begin, end) with a spring, its output at out + (b - begin) *
  // kSpringBlock (components out_stride apart): on the float lanes lanes(At, Share, arrays, ends,
  // laws, b, out), the block's kind dispatched once per run of blocks of one kind
  // (spring_lanes.cpp); else portable(b, dead_slots, out). A block with no spring gets 0.
  template <class Lanes, class Portable>
  void each_block(std::size_t begin, std::size_t end, Real* out, std::size_t out_stride,
                  const Lanes& lanes, const Portable& portable) const;
  // A kTwoStiffnesses block's second ks and kd, and bit l set where lane l takes them.
  struct SecondStiffness {
    Real ks = 0, kd = 0;
    uint32_t lanes = 0;
  };

  LaneBands layout_;
  const uint32_t* first_;
  const uint32_t* second_;
  // kd 0 where the spring is not damped; a dead slot's law is 0 (ks + kd = 0 says it is dead).
  AlignedBuffer<Real> rest_, ks_, kd_;
  std::vector<uint8_t> block_kind_;
  std::vector<uint32_t> block_first_, block_second_;  // per block: its lane 0's ends (kRunParity)
  // Per block: where kChosen, its chosen_; where kTwoStiffnesses, its second_stiffness_ (one
  // index into both, so a block reads one more array, not two).
  std::vector<uint32_t> block_extra_;
  std::vector<ChosenLanes<2>> chosen_;
  std::vector<SecondStiffness> second_stiffness_;
  std::vector<BlockLaw> block_law_;  // per block: its first live lane's law
  // The live slots' laws, block by block, lane by lane (what a block with dead slots loads on
  // lanes that expand loads), and per block where its own start.
  AlignedBuffer<Real> packed_rest_, packed_ks_, packed_kd_;
  std::vector<uint32_t> block_packed_;
  std::vector<uint32_t> block_live_;  // per block: bit l set where lane l lives
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

template <class Real, class Compute>
void LaneBands::fill_ring(const Band& band, const Real* full, Real* ring, std::ptrdiff_t from,
                          std::ptrdiff_t to, std::ptrdiff_t compute_from, std::ptrdiff_t compute_to,
                          const Compute& compute) const {
  const auto low = static_cast<std::ptrdiff_t>(band.low / kSpringBlock);
  const auto high = static_cast<std::ptrdiff_t>(band.high / kSpringBlock);
  const auto blocks = static_cast<std::ptrdiff_t>(band.ring_blocks);
  const std::size_t stride = slots();
  // Calls write(a, b, out) on the pieces of [begin, end) that do not wrap, out their ring slots.
  const auto in_ring = [&](std::ptrdiff_t begin, std::ptrdiff_t end, const auto& write) {
    while (begin < end) {
      const std::ptrdiff_t at = (begin % blocks + blocks) % blocks;
      const std::ptrdiff_t count = std::min(end - begin, blocks - at);
      Real* out = ring + band.ring_base + static_cast<std::size_t>(at) * kSpringBlock;
      write(begin, begin + count, out);
      if (at == 0) {  // the repeated first block
        for (std::size_t k = 0; k < 3; ++k)
          std::copy_n(out + k * ring_slots_, kSpringBlock,
                      out + k * ring_slots_ + band.ring_blocks * kSpringBlock);
      }
      begin += count;
    }
  };
  const auto full_slot = [&](std::ptrdiff_t block) {
    return band.base + static_cast<std::size_t>(block - low) * kSpringBlock;
  };
  const auto computed = [&](std::ptrdiff_t begin, std::ptrdiff_t end, Real* out) {
    compute(full_slot(begin) / kSpringBlock, full_slot(end) / kSpringBlock, out, ring_slots_);
  };
  const auto copied = [&](std::ptrdiff_t begin, std::ptrdiff_t end, Real* out) {
    const auto count = static_cast<std::size_t>(end - begin) * kSpringBlock;
    for (std::size_t k = 0; k < 3; ++k)
      std::copy_n(full + k * stride + full_slot(begin), count, out + k * ring_slots_);
  };
  const auto zeroed = [&](std::ptrdiff_t, std::ptrdiff_t, Real* out) {
    for (std::size_t k = 0; k < 3; ++k) std::fill_n(out + k * ring_slots_, kSpringBlock, Real(0));
  };
  from = std::max(from, low - 1);
  to = std::min(to, high + 1);
  for (std::ptrdiff_t block = from; block < to;) {
    std::ptrdiff_t next = block + 1;
    if (block < low || block >= high) {
      in_ring(block, next, zeroed);
    } else if (block >= compute_from && block < compute_to) {
      next = std::min({to, high, compute_to});
      in_ring(block, next, computed);
    } else {
      next = std::min({to, high, block < compute_from ? compute_from : to});
      in_ring(block, next, copied);
    }
    block = next;
  }
}

template <class Real, class Compute, class Sum, class AlsoCompute>
void LaneBands::sweep(int threads, bool parallel, const SlotBuffers<Real>& slots,
                      const Compute& compute, const Sum& sum, const LaneBands* also,
                      const SlotBuffers<Real>* also_slots, const AlsoCompute* also_compute) const {
  const std::size_t blocks = particle_blocks();
  const std::size_t tile = tile_;
  const std::size_t tiles = (blocks + tile - 1) / tile;
#pragma omp parallel num_threads(threads) if (parallel)
  {
    const auto count = static_cast<std::size_t>(omp_get_num_threads());
    const auto thread = static_cast<std::size_t>(omp_get_thread_num());
    const std::size_t first_tile = tiles * thread / count;
    const std::size_t last_tile = tiles * (thread + 1) / count;
    const std::size_t begin = std::min(blocks, first_tile * tile);
    const std::size_t end = std::min(blocks, last_tile * tile);
    const auto lead = [](const Band& band) {
      return (std::size_t{band.reach} + kSpringBlock - 1) / kSpringBlock;
    };
    // A later thread's sums read the first ends of a band's slots up to its reach back.
    const auto shared_from = [&](const Band& band) {
      return end == blocks ? end : std::max(begin, end - std::min(end, lead(band)));
    };
    const auto shared = [&](const LaneBands& layout, const SlotBuffers<Real>& buffers,
                            const auto& layout_compute) {
      const auto into_full = [&](std::size_t from, std::size_t to) {
        if (from < to) layout_compute(from, to, buffers.full + from * kSpringBlock, layout.slots());
      };
      for (std::size_t k = thread; k < layout.dead_blocks_.size(); k += count)
        into_full(layout.dead_blocks_[k], std::size_t{layout.dead_blocks_[k]} + 1);
      const std::size_t gathered = layout.slot_blocks() - layout.gathered_block_;
      into_full(layout.gathered_block_ + gathered * thread / count,
                layout.gathered_block_ + gathered * (thread + 1) / count);
      for (const Band& band : layout.bands_) band_blocks(band, shared_from(band), end, into_full);
    };
    // A tile's band blocks into the ring; the thread's first also those before it that its sums
    // read (computed by an earlier thread).
    const auto in_tile = [&](const LaneBands& layout, const SlotBuffers<Real>& buffers,
                             const auto& layout_compute, std::size_t tile_begin,
                             std::size_t tile_end) {
      Real* ring = buffers.rings + thread * 3 * layout.ring_slots_;
      for (const Band& band : layout.bands_) {
        const auto from = static_cast<std::ptrdiff_t>(tile_begin) -
                          static_cast<std::ptrdiff_t>(tile_begin == begin ? lead(band) : 0);
        layout.fill_ring(band, buffers.full, ring, from, static_cast<std::ptrdiff_t>(tile_end),
                         static_cast<std::ptrdiff_t>(begin),
                         static_cast<std::ptrdiff_t>(shared_from(band)), layout_compute);
      }
      return ring;
    };
    shared(*this, slots, compute);
    if (also != nullptr) shared(*also, *also_slots, *also_compute);
#pragma omp barrier
    for (std::size_t t = first_tile; t < last_tile; ++t) {
      const std::size_t tile_begin = t * tile, tile_end = std::min(blocks, tile_begin + tile);
      const Real* ring = in_tile(*this, slots, compute, tile_begin, tile_end);
      const Real* also_ring = also != nullptr
                                  ? in_tile(*also, *also_slots, *also_compute, tile_begin, tile_end)
                                  : nullptr;
      sum(t, tile_begin, tile_end, ring, also_ring);
    }
  }
}

}  // namespace clothlab::detail::inline CLOTHLAB_SIMD_NAMESPACE
