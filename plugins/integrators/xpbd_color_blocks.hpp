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
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <numeric>
#include <vector>

#include "float_lanes.hpp"
#include "simd_namespace.hpp"
#include "xpbd_constraint.hpp"
#include "xpbd_row_kernel.hpp"

namespace clothlab::builtin::inline CLOTHLAB_SIMD_NAMESPACE {

#if defined(CLOTHLAB_FLOAT_LANES)
namespace color_lanes {

using namespace detail;

class ColorBlocks {
 public:
  // springs: colour c's in [color_offsets[c], color_offsets[c + 1]). find_runs false: every
  // block gathered (what a test holds the runs against).
  void build(const std::vector<Constraint<float>>& springs,
             const std::vector<uint32_t>& color_offsets, bool find_runs = true) {
    first_.clear(), second_.clear(), rest_.clear(), ks_.clear(), kd_.clear();
    first_weight_.clear(), second_weight_.clear(), kind_.clear(), live_.clear();
    color_blocks_.assign(1, 0);
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
        const Kind kind = find_runs ? run_at(springs, order, p) : Kind::kGathered;
        if (kind == Kind::kGathered) {
          gathered.push_back(order[p++]);
          continue;
        }
        add_block(springs, &order[p], kLanes, kind);
        p += kLanes;
      }
      for (std::size_t g = 0; g < gathered.size(); g += kLanes)
        add_block(springs, &gathered[g], std::min(kLanes, gathered.size() - g), Kind::kGathered);
      color_blocks_.push_back(static_cast<uint32_t>(kind_.size()));
    }
  }

  std::size_t slots() const { return first_.size(); }
  // Colour c's blocks: [blocks_begin(c), blocks_begin(c + 1)).
  long blocks_begin(std::size_t color) const { return color_blocks_[color]; }
  // kSplitPairs: offset 1, firsts every other particle of a run of 2 kLanes (deinterleave<1>);
  // kSplitQuads: offset 2, the first two of every four (deinterleave<2>); kEveryOther: any
  // other offset, firsts every other particle, each end's run split and stored under a mask
  // (the other particles of its runs belong to other springs).
  enum class Kind : uint8_t { kInOrder, kSplitPairs, kSplitQuads, kEveryOther, kGathered };

  // How many blocks are of a kind.
  std::size_t blocks_of(Kind kind) const {
    return static_cast<std::size_t>(std::count(kind_.begin(), kind_.end(), kind));
  }

  // Projects block b's springs at x + dx; lambda by slot, reset where `fresh`.
  void project(long b, bool fresh, const float* x, float* dx, std::size_t stride, float h,
               float h_squared, float* lambda) const {
    switch (kind_[static_cast<std::size_t>(b)]) {
      case Kind::kInOrder:
        return project<Kind::kInOrder>(b, fresh, x, dx, stride, h, h_squared, lambda);
      case Kind::kSplitPairs:
        return project<Kind::kSplitPairs>(b, fresh, x, dx, stride, h, h_squared, lambda);
      case Kind::kSplitQuads:
        return project<Kind::kSplitQuads>(b, fresh, x, dx, stride, h, h_squared, lambda);
      case Kind::kEveryOther:
        return project<Kind::kEveryOther>(b, fresh, x, dx, stride, h, h_squared, lambda);
      case Kind::kGathered:
        return project<Kind::kGathered>(b, fresh, x, dx, stride, h, h_squared, lambda);
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

  // The block the kLanes springs from order[p] form, if they form one.
  static Kind run_at(const std::vector<Constraint<float>>& springs,
                     const std::vector<uint32_t>& order, std::size_t p) {
    if (p + kLanes > order.size()) return Kind::kGathered;
    const Constraint<float>& lead = springs[order[p]];
    const uint32_t offset = lead.second - lead.first;
    bool in_order = true, every_other = true, quads = offset == 2;
    for (std::size_t l = 1; l < kLanes; ++l) {
      const Constraint<float>& spring = springs[order[p + l]];
      if (spring.second - spring.first != offset) return Kind::kGathered;
      const uint32_t step = spring.first - lead.first;
      in_order = in_order && step == l;
      every_other = every_other && step == 2 * l;
      quads = quads && step == 4 * (l / 2) + l % 2;
    }
    if (in_order) return Kind::kInOrder;
    if (every_other) return offset == 1 ? Kind::kSplitPairs : Kind::kEveryOther;
    return quads ? Kind::kSplitQuads : Kind::kGathered;
  }

  // A block of `count` springs (ascending by first where a run), in its lanes' order; the
  // lanes past count are dead: weights and law 0, ends at particle 0, never stored.
  void add_block(const std::vector<Constraint<float>>& springs, const uint32_t* members,
                 std::size_t count, Kind kind) {
    std::vector<uint32_t> lane_member(members, members + count);
    if (kind != Kind::kInOrder && kind != Kind::kGathered) {
      const std::vector<uint32_t> positions =
          kind == Kind::kSplitQuads ? split_positions<2>() : split_positions<1>();
      const uint32_t base = springs[members[0]].first;
      for (std::size_t l = 0; l < kLanes; ++l)
        for (std::size_t m = 0; m < kLanes; ++m)
          if (springs[members[m]].first == base + positions[l]) lane_member[l] = members[m];
    }
    for (std::size_t l = 0; l < kLanes; ++l) {
      const Constraint<float> spring =
          l < count ? springs[lane_member[l]] : Constraint<float>{0, 0, 0, 0, 0, 0, 0};
      first_.push_back(spring.first), second_.push_back(spring.second);
      rest_.push_back(spring.rest), ks_.push_back(spring.ks), kd_.push_back(spring.kd);
      first_weight_.push_back(spring.first_weight);
      second_weight_.push_back(spring.second_weight);
    }
    kind_.push_back(kind);
    live_.push_back(static_cast<uint8_t>(count));
  }

  template <Kind kKind>
  void project(long b, bool fresh, const float* x, float* dx, std::size_t stride, float h,
               float h_squared, float* lambda) const {
    using namespace row_lanes;
    const std::size_t s = static_cast<std::size_t>(b) * kLanes;
    const uint32_t first = first_[s], second = second_[s];
    Floats x_difference[3], dxi[3], dxj[3];
    const auto split = [&](const float* p, Floats& at_first, Floats& at_second) {
      deinterleave<kKind == Kind::kSplitPairs ? 1 : 2>(
          load_floats(p + first), load_floats(p + first + kLanes), at_first, at_second);
    };
    for (std::size_t k = 0; k < 3; ++k) {
      const float* xk = x + k * stride;
      const float* dxk = dx + k * stride;
      if constexpr (kKind == Kind::kInOrder) {
        x_difference[k] = load_floats(xk + first) - load_floats(xk + second);
        dxi[k] = load_floats(dxk + first), dxj[k] = load_floats(dxk + second);
      } else if constexpr (kKind == Kind::kGathered) {
        const Indices i = load_indices(&first_[s]), j = load_indices(&second_[s]);
        x_difference[k] = gather_floats(xk, i) - gather_floats(xk, j);
        dxi[k] = gather_floats(dxk, i), dxj[k] = gather_floats(dxk, j);
      } else if constexpr (kKind == Kind::kEveryOther) {
        Floats xi, xj, odd;
        deinterleave<1>(load_floats(xk + first), load_floats(xk + first + kLanes), xi, odd);
        deinterleave<1>(load_floats(xk + second), load_floats(xk + second + kLanes), xj, odd);
        x_difference[k] = xi - xj;
        deinterleave<1>(load_floats(dxk + first), load_floats(dxk + first + kLanes), dxi[k], odd);
        deinterleave<1>(load_floats(dxk + second), load_floats(dxk + second + kLanes), dxj[k], odd);
      } else {
        Floats xi, xj;
        split(xk, xi, xj);
        x_difference[k] = xi - xj;
        split(dxk, dxi[k], dxj[k]);
      }
    }
    LawLanes law{};
    law.rest = load_floats(&rest_[s]);
    law.stiffness = load_floats(&ks_[s]) * broadcast(h_squared);
    law.damping = load_floats(&kd_[s]) * broadcast(h);
    law.compliance_scale = law.stiffness + law.damping;
    const Floats wi = load_floats(&first_weight_[s]), wj = load_floats(&second_weight_[s]);
    const Floats accumulated = fresh ? zero_floats() : load_floats(lambda + s);
    const SpringLanes u =
        spring_update(law, lanes_from_to(0, live_[static_cast<std::size_t>(b)]), x_difference, dxi,
                      dxj, inverse_denominator(law.compliance_scale, wi, wj), accumulated);
    store_floats(lambda + s, masked_add(u.pushed, accumulated, u.delta));
    const PushLanes<false> push(u, wi, wj);
    for (std::size_t k = 0; k < 3; ++k) {
      float* dxk = dx + k * stride;
      const Floats at_first = push.first_end(u.d[k], dxi[k]);
      const Floats at_second = push.second_end(u.d[k], dxj[k]);
      if constexpr (kKind == Kind::kInOrder) {
        store_floats(dxk + first, at_first), store_floats(dxk + second, at_second);
      } else if constexpr (kKind == Kind::kGathered) {
        float firsts[kLanes], seconds[kLanes];
        store_floats(firsts, at_first), store_floats(seconds, at_second);
        for (std::size_t l = 0; l < live_[static_cast<std::size_t>(b)]; ++l) {
          dxk[first_[s + l]] = firsts[l];
          dxk[second_[s + l]] = seconds[l];
        }
      } else if constexpr (kKind == Kind::kEveryOther) {
        const LaneMask even = greater(load_floats(kEvenLanes), zero_floats());
        Floats low, high;
        interleave<1>(at_first, at_first, low, high);
        store_floats(even, dxk + first, low), store_floats(even, dxk + first + kLanes, high);
        interleave<1>(at_second, at_second, low, high);
        store_floats(even, dxk + second, low), store_floats(even, dxk + second + kLanes, high);
      } else {
        Floats low, high;
        interleave<kKind == Kind::kSplitPairs ? 1 : 2>(at_first, at_second, low, high);
        store_floats(dxk + first, low), store_floats(dxk + first + kLanes, high);
      }
    }
  }

  // 1 in the even lanes: the particles of an every-other run that its block's springs hold.
  static constexpr float kEvenLanes[16] = {1, 0, 1, 0, 1, 0, 1, 0, 1, 0, 1, 0, 1, 0, 1, 0};

  // By slot, kLanes per block, in the lanes' order.
  std::vector<uint32_t> first_, second_;
  std::vector<float> rest_, ks_, kd_, first_weight_, second_weight_;
  std::vector<Kind> kind_;              // per block
  std::vector<uint8_t> live_;           // per block: its springs (the rest of its lanes are dead)
  std::vector<uint32_t> color_blocks_;  // colour c's blocks: [c], [c + 1])
};

}  // namespace color_lanes

using color_lanes::ColorBlocks;
#endif

}  // namespace clothlab::builtin::inline CLOTHLAB_SIMD_NAMESPACE
