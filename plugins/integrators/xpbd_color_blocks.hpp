// xpbd's general sweep on lanes (float32): each colour's springs in blocks of kLanes, projected
// with the grid's lane law (xpbd_row_kernel.hpp's spring_update), so a block's springs cost
// what a grid row's do where their ends lie as a grid row's would.
//
// Within a colour the springs are sorted by offset (second - first) and first particle, then
// cut into blocks whose ends load with plain loads: consecutive firsts of one offset (a
// vertical or diagonal stencil of a mesh numbered along rows), or the grid's in-row patterns
// (offset 1 or 2, every other first or every other pair), which load a run of 2 kLanes
// particles and split it. The springs that fit no such block are gathered and scattered
// by index. A colour's springs share no particle, so the order within it does not change
// the sweep, and each lane computes the same instructions whatever block it is in: the bits
// do not depend on how the springs were cut, nor on the thread count.
//
// A run with dead lanes (holes, or every other particle) would load and store its windows of
// particles under a mask, and a masked store is slow on AVX2. Where no particle of its windows
// belongs to a block that another thread projects at the same time (thread_share), nor lies
// past the last particle, the run loads its windows whole and stores each as it is in memory
// but for its live lanes (a select, then a plain store): what a masked store leaves, since
// nothing else writes those particles meanwhile.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <numeric>
#include <vector>

#include "float_lanes.hpp"
#include "simd_namespace.hpp"
#include "xpbd_constraint.hpp"
#include "xpbd_lane_blocks.hpp"
#include "xpbd_row_kernel.hpp"

namespace clothlab::builtin::inline CLOTHLAB_SIMD_NAMESPACE {

#if defined(CLOTHLAB_FLOAT_LANES)
namespace color_lanes {

using namespace detail;

class ColorBlocks final : public LaneBlocks {
 public:
  void build(const std::vector<Constraint<float>>& springs,
             const std::vector<uint32_t>& color_offsets, uint32_t particle_count, int threads,
             bool find_runs = true) override {
    first_.clear(), second_.clear(), rest_.clear(), ks_.clear(), kd_.clear();
    kind_.clear(), live_.clear(), live_bits_.clear(), lead_first_.clear(), lead_second_.clear();
    shared_law_.clear(), whole_windows_.clear();
    color_blocks_.assign(1, 0);
    threads_ = threads;
    std::vector<uint32_t> share(particle_count, kNoShare);  // find_whole_windows'
    for (std::size_t c = 0; c + 1 < color_offsets.size(); ++c) {
      std::vector<uint32_t> order(color_offsets[c + 1] - color_offsets[c]);
      std::iota(order.begin(), order.end(), color_offsets[c]);
      const auto offset = [&](uint32_t k) { return springs[k].second - springs[k].first; };
      std::sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) {
        return offset(a) != offset(b) ? offset(a) < offset(b) : springs[a].first < springs[b].first;
      });
      std::vector<uint32_t> gathered;
      std::size_t p = 0;
      while (p < order.size()) {
        const Run run = find_runs ? run_at(springs, order, p) : Run{Kind::kGathered, 1};
        if (run.kind == Kind::kGathered) {
          gathered.push_back(order[p++]);
          continue;
        }
        add_block(springs, &order[p], run.count, run.kind);
        p += run.count;
      }
      for (std::size_t g = 0; g < gathered.size(); g += kLanes)
        add_block(springs, &gathered[g], std::min(kLanes, gathered.size() - g), Kind::kGathered);
      find_whole_windows(color_blocks_.back(), static_cast<uint32_t>(kind_.size()), share);
      color_blocks_.push_back(static_cast<uint32_t>(kind_.size()));
    }
  }

  std::size_t slots() const override { return first_.size(); }
  long blocks_begin(std::size_t color) const override { return color_blocks_[color]; }
  void project(long begin, long end, const LaneArrays& arrays) const override {
    const bool whole = arrays.threads == threads_;  // the split the windows were found for
    for (long b = begin; b < end; ++b) project(b, arrays, whole);
  }
  // kSplitPairs: offset 1, firsts every other particle of a run of 2 kLanes (deinterleave<1>);
  // kSplitQuads: offset 2, the first two of every four (deinterleave<2>); kEveryOther: any
  // other offset, firsts every other particle, each end's run split and stored under a mask
  // (the other particles of its runs belong to other springs).
  enum class Kind : uint8_t { kInOrder, kSplitPairs, kSplitQuads, kEveryOther, kGathered };

  // How many blocks are of a kind.
  std::size_t blocks_of(Kind kind) const {
    return static_cast<std::size_t>(std::count(kind_.begin(), kind_.end(), kind));
  }
  // How many runs have dead lanes.
  std::size_t runs_with_holes() const {
    std::size_t count = 0;
    for (std::size_t b = 0; b < kind_.size(); ++b)
      count += kind_[b] != Kind::kGathered && live_[b] < kLanes;
    return count;
  }
  bool whole_windows(std::size_t b) const override { return whole_windows_[b] != 0; }
  std::vector<uint32_t> live_particles(std::size_t b) const override {
    std::vector<uint32_t> particles;
    for (std::size_t l = 0; l < kLanes; ++l)
      if (live_bits_[b] >> l & 1u)
        particles.push_back(first_[b * kLanes + l]), particles.push_back(second_[b * kLanes + l]);
    return particles;
  }
  std::vector<std::pair<uint32_t, uint32_t>> windows(std::size_t b) const override {
    if (kind_[b] == Kind::kGathered) return {};
    const uint32_t width = window_width(kind_[b]);
    return {{lead_first_[b], width}, {lead_second_[b], width}};
  }

  using Arrays = LaneArrays;

  // Projects block b's springs; `whole`: on the thread split the blocks were built for, so
  // those whose windows may be loaded and stored whole are.
  void project(long b, const Arrays& a, bool whole = false) const {
    const std::size_t block = static_cast<std::size_t>(b);
    const bool holes = live_[block] < kLanes;
    whole = whole && whole_windows_[block] != 0;
    switch (kind_[block]) {
      case Kind::kInOrder:
        if (!holes) return project<Kind::kInOrder, false, false>(b, a);
        return whole ? project<Kind::kInOrder, true, true>(b, a)
                     : project<Kind::kInOrder, true, false>(b, a);
      case Kind::kSplitPairs:
        return project<Kind::kSplitPairs, false, false>(b, a);
      case Kind::kSplitQuads:
        return project<Kind::kSplitQuads, false, false>(b, a);
      case Kind::kEveryOther:
        if (whole)
          return holes ? project<Kind::kEveryOther, true, true>(b, a)
                       : project<Kind::kEveryOther, false, true>(b, a);
        return holes ? project<Kind::kEveryOther, true, false>(b, a)
                     : project<Kind::kEveryOther, false, false>(b, a);
      case Kind::kGathered:
        return holes ? project<Kind::kGathered, true, false>(b, a)
                     : project<Kind::kGathered, false, false>(b, a);
    }
  }

 private:
  // The lane order of a split run: where in the run each lane's first end lies.
  template <int Step>
  static std::vector<uint32_t> split_positions() {
    float run[2 * kLanes];
    for (std::size_t k = 0; k < 2 * kLanes; ++k) run[k] = static_cast<float>(k);
    Floats starts, partners;
    deinterleave<Step>(load_floats(run), load_floats(run + kLanes), starts, partners);
    float lanes[kLanes];
    store_floats(lanes, starts);
    return {lanes, lanes + kLanes};
  }

  static constexpr uint32_t kNoShare = ~0u;

  // The particles a run's window holds: its lanes, or every other particle of twice as many.
  static uint32_t window_width(Kind kind) {
    return static_cast<uint32_t>(kind == Kind::kInOrder ? kLanes : 2 * kLanes);
  }

  // Which of a colour's blocks [begin, end) may load and store their windows whole: the runs
  // with dead lanes whose windows lie within the particles and hold none that a block of
  // another thread's share (thread_share over threads_) joins or stores whole. `share`: per
  // particle, the share whose blocks join it, kNoShare throughout, and so again on return.
  void find_whole_windows(uint32_t begin, uint32_t end, std::vector<uint32_t>& share) {
    const auto mark = [&](uint32_t b, uint32_t value) {
      for (std::size_t l = 0; l < kLanes; ++l)
        if (live_bits_[b] >> l & 1u)
          share[first_[b * kLanes + l]] = value, share[second_[b * kLanes + l]] = value;
    };
    std::vector<uint32_t> share_of_block(end - begin), claimed;
    for (long t = 0; t < threads_; ++t) {
      const auto [first, last] = thread_share(begin, end, t, threads_);
      for (long b = first; b < last; ++b) {
        share_of_block[static_cast<std::size_t>(b - begin)] = static_cast<uint32_t>(t);
        mark(static_cast<uint32_t>(b), static_cast<uint32_t>(t));
      }
    }
    for (uint32_t b = begin; b < end; ++b) {
      const uint32_t own = share_of_block[b - begin];
      bool whole =
          kind_[b] == Kind::kEveryOther || (kind_[b] == Kind::kInOrder && live_[b] < kLanes);
      const uint32_t width = window_width(kind_[b]);
      for (const uint32_t start : {lead_first_[b], lead_second_[b]})
        for (uint32_t particle = start; whole && particle < start + width; ++particle)
          whole =
              particle < share.size() && (share[particle] == kNoShare || share[particle] == own);
      whole_windows_.push_back(whole);
      // A particle no block joins is claimed by the first share that stores it whole, so that
      // no two threads store it, even its unchanged value.
      if (whole)
        for (const uint32_t start : {lead_first_[b], lead_second_[b]})
          for (uint32_t particle = start; particle < start + width; ++particle)
            if (share[particle] == kNoShare) share[particle] = own, claimed.push_back(particle);
    }
    for (uint32_t b = begin; b < end; ++b) mark(b, kNoShare);
    for (const uint32_t particle : claimed) share[particle] = kNoShare;
  }

  // A block from order[p]: its kind and how many springs it takes.
  struct Run {
    Kind kind;
    std::size_t count;
  };

  // The springs from order[p] of its offset that lie in a run from its first particle: every
  // particle of kLanes, or every other of 2 kLanes (the run ends at one that does not), with
  // dead lanes where a spring is missing, if they fill a quarter of its lanes. A full run of
  // offset 1 or 2 is split without masks.
  static Run run_at(const std::vector<Constraint<float>>& springs,
                    const std::vector<uint32_t>& order, std::size_t p) {
    const Constraint<float>& lead = springs[order[p]];
    const uint32_t offset = lead.second - lead.first;
    const auto steps = [&](auto fits) {
      std::size_t n = 0;
      for (; p + n < order.size(); ++n) {
        const Constraint<float>& spring = springs[order[p + n]];
        if (spring.second - spring.first != offset || !fits(spring.first - lead.first)) break;
      }
      return n;
    };
    const std::size_t in_order = steps([](uint32_t step) { return step < kLanes; });
    const std::size_t every_other =
        steps([](uint32_t step) { return step < 2 * kLanes && step % 2 == 0; });
    if (offset == 2 && p + kLanes <= order.size()) {
      bool quads = true;
      for (std::size_t l = 0; l < kLanes; ++l)
        quads = quads && springs[order[p + l]].second - springs[order[p + l]].first == offset &&
                springs[order[p + l]].first - lead.first == 4 * (l / 2) + l % 2;
      if (quads) return {Kind::kSplitQuads, kLanes};
    }
    if (every_other == kLanes && offset == 1) return {Kind::kSplitPairs, kLanes};
    if (4 * std::max(in_order, every_other) < kLanes) return {Kind::kGathered, 1};
    return in_order >= every_other ? Run{Kind::kInOrder, in_order}
                                   : Run{Kind::kEveryOther, every_other};
  }

  // A block of `count` springs (ascending by first), in its lanes' order. A dead lane (no
  // spring: law 0, outside the block's live lanes, never stored) of a run joins its run's
  // particles, of a gathered block particle 0 to itself.
  void add_block(const std::vector<Constraint<float>>& springs, const uint32_t* members,
                 std::size_t count, Kind kind) {
    constexpr uint32_t kDead = ~0u;
    std::vector<uint32_t> lane_member(kLanes, kDead);
    std::vector<uint32_t> positions(kLanes);
    std::iota(positions.begin(), positions.end(), 0u);
    if (kind == Kind::kSplitQuads) positions = split_positions<2>();
    if (kind == Kind::kSplitPairs || kind == Kind::kEveryOther) positions = split_positions<1>();
    const uint32_t base = springs[members[0]].first;
    const uint32_t offset = springs[members[0]].second - base;
    for (std::size_t m = 0; m < count; ++m) {
      if (kind == Kind::kGathered) {
        lane_member[m] = members[m];
        continue;
      }
      const auto lane =
          std::find(positions.begin(), positions.end(), springs[members[m]].first - base) -
          positions.begin();
      lane_member[static_cast<std::size_t>(lane)] = members[m];
    }
    uint32_t live_bits = 0;
    bool shared_law = true;
    const Constraint<float>& lead = springs[members[0]];
    for (std::size_t l = 0; l < kLanes; ++l) {
      const uint32_t at = kind == Kind::kGathered ? 0u : base + positions[l];
      const Constraint<float> spring =
          lane_member[l] != kDead
              ? springs[lane_member[l]]
              : Constraint<float>{at, kind == Kind::kGathered ? at : at + offset, 0, 0, 0, 0, 0};
      first_.push_back(spring.first), second_.push_back(spring.second);
      rest_.push_back(spring.rest), ks_.push_back(spring.ks), kd_.push_back(spring.kd);
      if (lane_member[l] == kDead) continue;
      live_bits |= 1u << l;
      shared_law =
          shared_law && spring.rest == lead.rest && spring.ks == lead.ks && spring.kd == lead.kd;
    }
    kind_.push_back(kind);
    live_.push_back(static_cast<uint8_t>(count));
    live_bits_.push_back(live_bits);
    lead_first_.push_back(first_[first_.size() - kLanes]);
    lead_second_.push_back(second_[second_.size() - kLanes]);
    shared_law_.push_back(shared_law);
  }

  // Holes: some lanes dead (no spring), whose particles a run neither changes nor, unless
  // kWhole (its windows loaded and stored whole), reads.
  template <Kind kKind, bool kHoles, bool kWhole>
  void project(long b, const Arrays& a) const {
    using namespace row_lanes;
    const std::size_t block = static_cast<std::size_t>(b);
    const std::size_t s = block * kLanes;
    const uint32_t first = lead_first_[block], second = lead_second_[block];
    const std::size_t stride = a.stride;
    const LaneMask live = kHoles ? lanes_of_bits(live_bits_[block]) : all_lanes();
    // An every-other run's particles that live lanes hold, in its two halves.
    LaneMask low_half = all_lanes(), high_half = all_lanes();
    if constexpr (kKind == Kind::kEveryOther) {
      Floats low, high;
      interleave<1>(keep(live, broadcast(1.0f)), zero_floats(), low, high);
      low_half = greater(low, zero_floats()), high_half = greater(high, zero_floats());
    }
    constexpr bool kMasked = !kWhole && (kHoles || kKind == Kind::kEveryOther);
    const auto load = [&](LaneMask lanes, const float* p) {
      if constexpr (kMasked)
        return load_floats(lanes, p);
      else
        return load_floats(p);
    };
    // Whole: read again before the store, as the block's other window may have changed it.
    const auto store = [&](LaneMask lanes, float* p, Floats value) {
      if constexpr (kMasked)
        store_floats(lanes, p, value);
      else if constexpr (kWhole)
        store_floats(p, select(lanes, value, load_floats(p)));
      else
        store_floats(p, value);
    };
    Floats x_difference[3], dxi[3], dxj[3], wi, wj;
    const auto split = [&](const float* p, Floats& value) {  // an every-other run's lanes
      Floats odd;
      deinterleave<1>(load(low_half, p), load(high_half, p + kLanes), value, odd);
    };
    if constexpr (kKind == Kind::kInOrder) {
      wi = load(live, a.w + first), wj = load(live, a.w + second);
    } else if constexpr (kKind == Kind::kGathered) {
      wi = gather_floats(a.w, load_indices(&first_[s]));
      wj = gather_floats(a.w, load_indices(&second_[s]));
    } else if constexpr (kKind == Kind::kEveryOther) {
      split(a.w + first, wi), split(a.w + second, wj);
    } else {
      constexpr int kStep = kKind == Kind::kSplitPairs ? 1 : 2;
      deinterleave<kStep>(load_floats(a.w + first), load_floats(a.w + first + kLanes), wi, wj);
    }
    for (std::size_t k = 0; k < 3; ++k) {
      const float* xk = a.x + k * stride;
      const float* dxk = a.dx + k * stride;
      if constexpr (kKind == Kind::kInOrder) {
        x_difference[k] = load(live, xk + first) - load(live, xk + second);
        dxi[k] = load(live, dxk + first), dxj[k] = load(live, dxk + second);
      } else if constexpr (kKind == Kind::kGathered) {
        const Indices i = load_indices(&first_[s]), j = load_indices(&second_[s]);
        x_difference[k] = gather_floats(xk, i) - gather_floats(xk, j);
        dxi[k] = gather_floats(dxk, i), dxj[k] = gather_floats(dxk, j);
      } else if constexpr (kKind == Kind::kEveryOther) {
        Floats xi, xj;
        split(xk + first, xi), split(xk + second, xj);
        x_difference[k] = xi - xj;
        split(dxk + first, dxi[k]), split(dxk + second, dxj[k]);
      } else {
        constexpr int kStep = kKind == Kind::kSplitPairs ? 1 : 2;
        Floats xi, xj;
        deinterleave<kStep>(load_floats(xk + first), load_floats(xk + first + kLanes), xi, xj);
        x_difference[k] = xi - xj;
        deinterleave<kStep>(load_floats(dxk + first), load_floats(dxk + first + kLanes), dxi[k],
                            dxj[k]);
      }
    }
    // A law the block's springs share is read once: the same values in every lane.
    const LawLanes law =
        shared_law_[block]
            ? law_lanes(broadcast(rest_[s]), broadcast(ks_[s]) * broadcast(a.h_squared),
                        broadcast(kd_[s]) * broadcast(a.h))
            : law_lanes(load_floats(&rest_[s]), load_floats(&ks_[s]) * broadcast(a.h_squared),
                        load_floats(&kd_[s]) * broadcast(a.h));
    const Floats accumulated = a.fresh ? zero_floats() : load_floats(a.lambda + s);
    const SpringLanes u =
        spring_update(law, live, x_difference, dxi, dxj,
                      inverse_denominator(law.compliance_scale, wi, wj), accumulated);
    if (a.keep) store_floats(a.lambda + s, masked_add(u.pushed, accumulated, u.delta));
    const PushLanes<false> push(u, wi, wj);
    for (std::size_t k = 0; k < 3; ++k) {
      float* dxk = a.dx + k * stride;
      const Floats at_first = push.first_end(u.d[k], dxi[k]);
      const Floats at_second = push.second_end(u.d[k], dxj[k]);
      if constexpr (kKind == Kind::kInOrder) {
        store(live, dxk + first, at_first), store(live, dxk + second, at_second);
      } else if constexpr (kKind == Kind::kGathered) {
        float firsts[kLanes], seconds[kLanes];
        store_floats(firsts, at_first), store_floats(seconds, at_second);
        for (std::size_t l = 0; l < live_[static_cast<std::size_t>(b)]; ++l) {
          dxk[first_[s + l]] = firsts[l];
          dxk[second_[s + l]] = seconds[l];
        }
      } else if constexpr (kKind == Kind::kEveryOther) {
        Floats low, high;
        interleave<1>(at_first, at_first, low, high);
        store(low_half, dxk + first, low), store(high_half, dxk + first + kLanes, high);
        interleave<1>(at_second, at_second, low, high);
        store(low_half, dxk + second, low), store(high_half, dxk + second + kLanes, high);
      } else {
        Floats low, high;
        interleave<kKind == Kind::kSplitPairs ? 1 : 2>(at_first, at_second, low, high);
        store_floats(dxk + first, low), store_floats(dxk + first + kLanes, high);
      }
    }
  }

  // By slot, kLanes per block, in the lanes' order: what a gathered block loads, and the laws
  // of blocks that do not share one (a sweep reads neither of the others, so they cost no
  // memory traffic).
  std::vector<uint32_t> first_, second_;
  std::vector<float> rest_, ks_, kd_;
  // Per block.
  std::vector<Kind> kind_;
  std::vector<uint8_t> live_;                       // its springs (the rest of its lanes are dead)
  std::vector<uint32_t> live_bits_;                 // its live lanes
  std::vector<uint32_t> lead_first_, lead_second_;  // lane 0's ends (a run's starts)
  std::vector<uint8_t> shared_law_;                 // whether its springs share one law
  std::vector<uint8_t> whole_windows_;              // whether it loads and stores them whole
  std::vector<uint32_t> color_blocks_;              // colour c's blocks: [c], [c + 1])
  int threads_ = 1;                                 // the threads whole windows were found for
};

}  // namespace color_lanes

using color_lanes::ColorBlocks;
#endif

}  // namespace clothlab::builtin::inline CLOTHLAB_SIMD_NAMESPACE
