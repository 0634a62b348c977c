#include "spring_lanes.hpp"

#include <algorithm>
#include <numeric>
#include <type_traits>

#include "spring_kernel.hpp"

namespace clothlab::detail::inline CLOTHLAB_SIMD_NAMESPACE {
namespace {

bool consecutive(const uint32_t* values) {
  for (std::size_t l = 1; l < kSpringBlock; ++l)
    if (values[l] != values[0] + l) return false;
  return true;
}

}  // namespace

template <class Real>
SpringLanes<Real>::SpringLanes(const ClothModel& model, bool damped)
    : springs_(model.spring_count()), damped_(damped) {
  std::vector<uint32_t> order(springs_);
  std::iota(order.begin(), order.end(), 0u);
  std::stable_sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) {
    const uint32_t offset_a = model.second[a] - model.first[a];
    const uint32_t offset_b = model.second[b] - model.first[b];
    return offset_a != offset_b ? offset_a < offset_b : model.first[a] < model.first[b];
  });

  const std::size_t slots = (springs_ / kSpringBlock + 1) * kSpringBlock;
  const auto zero_slot = static_cast<uint32_t>(springs_);
  first_ = AlignedBuffer<uint32_t>(slots);
  second_ = AlignedBuffer<uint32_t>(slots);
  rest_ = AlignedBuffer<Real>(slots);
  ks_ = AlignedBuffer<Real>(slots);
  kd_ = AlignedBuffer<Real>(slots);
  std::vector<uint32_t> slot_of(springs_);  // model spring -> slot
  for (std::size_t s = 0; s < springs_; ++s) {
    const uint32_t spring = order[s];
    slot_of[spring] = static_cast<uint32_t>(s);
    first_[s] = model.first[spring];
    second_[s] = model.second[spring];
    rest_[s] = static_cast<Real>(model.rest_length[spring]);
    ks_[s] = static_cast<Real>(model.ks[spring]);
    const bool has_damping = damped && model.kd[spring] > 0.0;
    kd_[s] = has_damping ? static_cast<Real>(model.kd[spring]) : Real(0);
    damped_count_ += has_damping;
  }
  for (std::size_t b = 0; b < slots / kSpringBlock; ++b) {
    const std::size_t s = b * kSpringBlock;
    bool one_law = true;
    for (std::size_t l = 1; l < kSpringBlock; ++l)
      one_law = one_law && rest_[s + l] == rest_[s] && ks_[s + l] == ks_[s] && kd_[s + l] == kd_[s];
    const bool in_order = consecutive(&first_[s]) && consecutive(&second_[s]);
    block_kind_.push_back(
        static_cast<uint8_t>((in_order ? kEndsInOrder : 0) | (one_law ? kOneLaw : 0)));
    block_first_.push_back(first_[s]);
    block_second_.push_back(second_[s]);
    block_law_.push_back({rest_[s], ks_[s], kd_[s]});
  }

  // Each particle's entries, ascending by slot.
  const std::size_t particles = model.particle_count;
  const std::size_t blocks = (particles + kSpringBlock - 1) / kSpringBlock;
  std::vector<std::vector<uint32_t>> incident(particles);
  for (std::size_t i = 0; i < particles; ++i) {
    for (uint32_t e = model.adjacency_offsets[i]; e < model.adjacency_offsets[i + 1]; ++e) {
      const uint32_t spring = model.adjacent_springs[e];
      incident[i].push_back(slot_of[spring]);
    }
    std::sort(incident[i].begin(), incident[i].end());
    for (uint32_t& slot : incident[i])
      if (second_[slot] == i) slot |= kSecondEnd;
  }
  row_begin_.assign(blocks + 1, 0);
  for (std::size_t b = 0; b < blocks; ++b) {
    std::size_t widest = 0;
    for (std::size_t i = b * kSpringBlock; i < std::min(particles, (b + 1) * kSpringBlock); ++i)
      widest = std::max(widest, incident[i].size());
    row_begin_[b + 1] = row_begin_[b] + static_cast<uint32_t>(widest);
  }
  entries_ = AlignedBuffer<uint32_t>(std::size_t{row_begin_[blocks]} * kSpringBlock);
  row_in_order_.resize(row_begin_[blocks]);
  row_first_.resize(row_begin_[blocks]);
  for (std::size_t b = 0; b < blocks; ++b)
    for (uint32_t r = row_begin_[b]; r < row_begin_[b + 1]; ++r) {
      uint32_t* row = &entries_[std::size_t{r} * kSpringBlock];
      for (std::size_t l = 0; l < kSpringBlock; ++l) {
        const std::size_t i = b * kSpringBlock + l;
        const std::size_t k = r - row_begin_[b];
        row[l] = i < particles && k < incident[i].size() ? incident[i][k] : zero_slot;
      }
      row_in_order_[r] = consecutive(row);
      row_first_[r] = row[0];
    }
}

namespace {

template <class Real, bool Damped>
void spring_block_portable(const Real* x, const Real* v, std::size_t stride, std::size_t block,
                           const uint32_t* first, const uint32_t* second, const Real* rest,
                           const Real* ks, const Real* kd, std::size_t slots, Real* force) {
  for (std::size_t s = block * kSpringBlock; s < (block + 1) * kSpringBlock; ++s) {
    const std::size_t i = first[s], j = second[s];
    Real d[3], dv[3] = {0, 0, 0};
    for (std::size_t k = 0; k < 3; ++k) {
      d[k] = x[j + k * stride] - x[i + k * stride];
      if constexpr (Damped) dv[k] = v[j + k * stride] - v[i + k * stride];
    }
    const Real scale =
        spring_force_scale<Damped>(d[0], d[1], d[2], dv[0], dv[1], dv[2], rest[s], ks[s], kd[s]);
    for (std::size_t k = 0; k < 3; ++k) force[k * slots + s] = scale * d[k];
  }
}

#if defined(CLOTHLAB_FLOAT_LANES)
// The arrays a block reads where its ends are not in order or its lanes' laws differ.
struct SpringArrays {
  const uint32_t* first;
  const uint32_t* second;
  const float* rest;
  const float* ks;
  const float* kd;
};

// The block of springs from slot s: ends in order (runs from particles first and second) or
// gathered by the lanes' indices; one law (rest, ks, kd) broadcast or a law per lane.
template <bool Damped, bool InOrder, bool OneLaw>
void spring_block_lanes(const float* x, const float* v, std::size_t stride, std::size_t s,
                        uint32_t first, uint32_t second, const float (&law)[3],
                        const SpringArrays& arrays, float* force, std::size_t slots) {
  Floats d[3], dv[3] = {};
  if constexpr (InOrder) {
    for (std::size_t k = 0; k < 3; ++k) {
      d[k] = load_floats(x + k * stride + second) - load_floats(x + k * stride + first);
      if constexpr (Damped)
        dv[k] = load_floats(v + k * stride + second) - load_floats(v + k * stride + first);
    }
  } else {
    const Indices i = load_indices(arrays.first + s), j = load_indices(arrays.second + s);
    for (std::size_t k = 0; k < 3; ++k) {
      d[k] = gather_floats(x + k * stride, j) - gather_floats(x + k * stride, i);
      if constexpr (Damped)
        dv[k] = gather_floats(v + k * stride, j) - gather_floats(v + k * stride, i);
    }
  }
  Floats rest, ks, kd;
  if constexpr (OneLaw) {
    rest = broadcast(law[0]), ks = broadcast(law[1]), kd = broadcast(law[2]);
  } else {
    rest = load_floats(arrays.rest + s), ks = load_floats(arrays.ks + s);
    kd = load_floats(arrays.kd + s);
  }
  const Floats scale =
      spring_force_scale<Damped>(d[0], d[1], d[2], dv[0], dv[1], dv[2], rest, ks, kd);
  for (std::size_t k = 0; k < 3; ++k) store_floats(force + k * slots + s, scale * d[k]);
}

template <bool Damped>
void spring_block_lanes(bool in_order, bool one_law, const float* x, const float* v,
                        std::size_t stride, std::size_t s, uint32_t first, uint32_t second,
                        const float (&law)[3], const SpringArrays& arrays, float* force,
                        std::size_t slots) {
  if (in_order && one_law)
    spring_block_lanes<Damped, true, true>(x, v, stride, s, first, second, law, arrays, force,
                                           slots);
  else if (in_order)
    spring_block_lanes<Damped, true, false>(x, v, stride, s, first, second, law, arrays, force,
                                            slots);
  else if (one_law)
    spring_block_lanes<Damped, false, true>(x, v, stride, s, first, second, law, arrays, force,
                                            slots);
  else
    spring_block_lanes<Damped, false, false>(x, v, stride, s, first, second, law, arrays, force,
                                             slots);
}
#endif

}  // namespace

template <class Real>
void SpringLanes<Real>::forces(const Real* x, const Real* v, std::size_t stride, std::size_t begin,
                               std::size_t end, Real* force) const {
  const bool damped = v != nullptr && damped_count_ > 0;
  for (std::size_t b = begin; b < end; ++b) {
#if defined(CLOTHLAB_FLOAT_LANES)
    if constexpr (std::is_same_v<Real, float>) {
      const SpringArrays arrays{first_.data(), second_.data(), rest_.data(), ks_.data(),
                                kd_.data()};
      const float law[3] = {block_law_[b].rest, block_law_[b].ks, block_law_[b].kd};
      const bool in_order = (block_kind_[b] & kEndsInOrder) != 0;
      const bool one_law = (block_kind_[b] & kOneLaw) != 0;
      const std::size_t s = b * kSpringBlock;
      if (damped)
        spring_block_lanes<true>(in_order, one_law, x, v, stride, s, block_first_[b],
                                 block_second_[b], law, arrays, force, slots());
      else
        spring_block_lanes<false>(in_order, one_law, x, v, stride, s, block_first_[b],
                                  block_second_[b], law, arrays, force, slots());
      continue;
    }
#endif
    if (damped)
      spring_block_portable<Real, true>(x, v, stride, b, first_.data(), second_.data(),
                                        rest_.data(), ks_.data(), kd_.data(), slots(), force);
    else
      spring_block_portable<Real, false>(x, v, stride, b, first_.data(), second_.data(),
                                         rest_.data(), ks_.data(), kd_.data(), slots(), force);
  }
  // The padding joins particle 0 to itself, which is 0 only while particle 0 is finite: the
  // zero slot must stay 0 whatever the state.
  if (end == spring_blocks())
    for (std::size_t k = 0; k < 3; ++k)
      std::fill(force + k * slots() + springs_, force + (k + 1) * slots(), Real(0));
}

template <class Real>
void SpringLanes<Real>::sum_incident(const Real* per_slot, std::size_t block,
                                     Real (&sum)[3][kSpringBlock]) const {
  const std::size_t stride = slots();
#if defined(CLOTHLAB_FLOAT_LANES)
  if constexpr (std::is_same_v<Real, float>) {
    Floats total[3] = {zero_floats(), zero_floats(), zero_floats()};
    for (uint32_t r = row_begin_[block]; r < row_begin_[block + 1]; ++r) {
      if (row_in_order_[r]) {
        const std::size_t slot = row_first_[r] & ~kSecondEnd;
        const bool subtract = (row_first_[r] & kSecondEnd) != 0;
        for (std::size_t k = 0; k < 3; ++k) {
          const Floats value = load_floats(per_slot + k * stride + slot);
          total[k] = subtract ? total[k] - value : total[k] + value;
        }
      } else {
        const Indices entry = load_indices(&entries_[std::size_t{r} * kSpringBlock]);
        const Indices slot = without_top_bit(entry);
        for (std::size_t k = 0; k < 3; ++k)
          total[k] =
              total[k] + negated_where_top_bit(gather_floats(per_slot + k * stride, slot), entry);
      }
    }
    for (std::size_t k = 0; k < 3; ++k) store_floats(sum[k], total[k]);
    return;
  }
#endif
  for (std::size_t k = 0; k < 3; ++k) std::fill(sum[k], sum[k] + kSpringBlock, Real(0));
  for (uint32_t r = row_begin_[block]; r < row_begin_[block + 1]; ++r) {
    const uint32_t* row = &entries_[std::size_t{r} * kSpringBlock];
    for (std::size_t l = 0; l < kSpringBlock; ++l) {
      const std::size_t slot = row[l] & ~kSecondEnd;
      const bool subtract = (row[l] & kSecondEnd) != 0;
      for (std::size_t k = 0; k < 3; ++k) {
        const Real value = per_slot[k * stride + slot];
        sum[k][l] = subtract ? sum[k][l] - value : sum[k][l] + value;
      }
    }
  }
}

template class SpringLanes<float>;
template class SpringLanes<double>;

}  // namespace clothlab::detail::inline CLOTHLAB_SIMD_NAMESPACE
