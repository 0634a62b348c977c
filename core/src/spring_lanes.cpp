#include "spring_lanes.hpp"

#include <algorithm>
#include <numeric>
#include <type_traits>

#include "inverse_sqrt.hpp"
#include "jacobian_row_kernel.hpp"
#include "spring_kernel.hpp"

namespace clothlab::detail::inline CLOTHLAB_SIMD_NAMESPACE {
namespace {

// An offset's springs form a band where they fill at least 1 / kBandShare of its range's slots:
// a dead lane computed in order costs less than a live one gathered.
constexpr std::size_t kBandShare = 5;

bool consecutive(const uint32_t* values) {
  for (std::size_t l = 1; l < kSpringBlock; ++l)
    if (values[l] != values[0] + l) return false;
  return true;
}

}  // namespace

template <class Real>
SpringLanes<Real>::SpringLanes(const ClothModel& model, bool damped)
    : springs_(model.spring_count()), damped_(damped) {
  const std::size_t particles = model.particle_count;
  std::vector<uint32_t> order(springs_);
  std::iota(order.begin(), order.end(), 0u);
  const auto offset_of = [&](uint32_t spring) {
    return model.second[spring] - model.first[spring];
  };
  std::stable_sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) {
    return offset_of(a) != offset_of(b) ? offset_of(a) < offset_of(b)
                                        : model.first[a] < model.first[b];
  });

  std::vector<uint32_t> slot_of(springs_);  // model spring -> slot
  std::vector<uint32_t> gathered;           // the springs in no band, in order
  std::size_t next = kSpringBlock;          // after the leading dead block
  for (std::size_t begin = 0, end = 0; begin < springs_; begin = end) {
    const uint32_t offset = offset_of(order[begin]);
    bool distinct = true;
    for (end = begin + 1; end < springs_ && offset_of(order[end]) == offset; ++end)
      distinct = distinct && model.first[order[end]] != model.first[order[end - 1]];
    const auto block = static_cast<uint32_t>(kSpringBlock);
    const uint32_t low = model.first[order[begin]] / block * block;
    const uint32_t high = (model.first[order[end - 1]] / block + 1) * block;
    if (!distinct || kBandShare * (end - begin) < high - low) {
      gathered.insert(gathered.end(), order.begin() + static_cast<std::ptrdiff_t>(begin),
                      order.begin() + static_cast<std::ptrdiff_t>(end));
      continue;
    }
    bands_.push_back({offset, low, high, next});
    dead_blocks_.push_back(static_cast<uint32_t>((next + high - low) / kSpringBlock));
    for (std::size_t k = begin; k < end; ++k)
      slot_of[order[k]] = static_cast<uint32_t>(next + model.first[order[k]] - low);
    next += high - low + kSpringBlock;  // and a dead block after it
  }
  const std::size_t gathered_base = next;
  gathered_block_ = gathered_base / kSpringBlock;
  dead_blocks_.push_back(0);
  for (std::size_t k = 0; k < gathered.size(); ++k)
    slot_of[gathered[k]] = static_cast<uint32_t>(gathered_base + k);

  const std::size_t slots =
      gathered_base + (gathered.size() + kSpringBlock - 1) / kSpringBlock * kSpringBlock;
  first_ = AlignedBuffer<uint32_t>(slots);
  second_ = AlignedBuffer<uint32_t>(slots);
  rest_ = AlignedBuffer<Real>(slots);
  ks_ = AlignedBuffer<Real>(slots);
  kd_ = AlignedBuffer<Real>(slots);
  // Zeroed: every slot dead (law 0), joining particle 0 to itself.
  spring_in_.assign(slots, static_cast<uint32_t>(springs_));
  std::vector<uint8_t> live(slots, 0);
  // A band's dead slots join its own particles where they exist, so its blocks stay in order.
  for (const Band& band : bands_)
    for (uint32_t i = band.low; i < band.high && std::size_t{i} + band.offset < particles; ++i) {
      first_[band.base + i - band.low] = i;
      second_[band.base + i - band.low] = i + band.offset;
    }
  for (std::size_t spring = 0; spring < springs_; ++spring) {
    const std::size_t s = slot_of[spring];
    first_[s] = model.first[spring];
    second_[s] = model.second[spring];
    rest_[s] = static_cast<Real>(model.rest_length[spring]);
    ks_[s] = static_cast<Real>(model.ks[spring]);
    const bool has_damping = damped && model.kd[spring] > 0.0;
    kd_[s] = has_damping ? static_cast<Real>(model.kd[spring]) : Real(0);
    live[s] = 1;
    spring_in_[s] = static_cast<uint32_t>(spring);
    damped_count_ += has_damping;
  }
  for (std::size_t b = 0; b < slots / kSpringBlock; ++b) {
    const std::size_t s = b * kSpringBlock;
    bool one_law = true, any_live = false, all_live = true;
    for (std::size_t l = 0; l < kSpringBlock; ++l) {
      one_law = one_law && rest_[s + l] == rest_[s] && ks_[s + l] == ks_[s] && kd_[s + l] == kd_[s];
      any_live = any_live || live[s + l] != 0;
      all_live = all_live && live[s + l] != 0;
    }
    const bool in_order = consecutive(&first_[s]) && consecutive(&second_[s]);
    block_kind_.push_back(
        static_cast<uint8_t>((in_order ? kEndsInOrder : 0) | (one_law && all_live ? kOneLaw : 0) |
                             (all_live ? 0 : kDeadSlots) | (any_live ? 0 : kNoSpring)));
    block_first_.push_back(first_[s]);
    block_second_.push_back(second_[s]);
    block_law_.push_back({rest_[s], ks_[s], kd_[s]});
  }

  // Each particle's gathered entries, ascending by slot.
  const std::size_t blocks = (particles + kSpringBlock - 1) / kSpringBlock;
  std::vector<std::vector<uint32_t>> incident(particles);
  for (std::size_t i = 0; i < particles; ++i) {
    for (uint32_t e = model.adjacency_offsets[i]; e < model.adjacency_offsets[i + 1]; ++e) {
      const uint32_t slot = slot_of[model.adjacent_springs[e]];
      if (slot >= gathered_base) incident[i].push_back(slot);
    }
    std::sort(incident[i].begin(), incident[i].end());
    for (uint32_t& slot : incident[i])
      if (second_[slot] == i) slot |= kSecondEnd;
  }
  // Per particle block: each band's rows (the block's particles as first ends, then as second
  // ends, where the band reaches them), then its gathered rows.
  std::vector<uint32_t> rows;
  row_begin_.assign(1, 0);
  for (std::size_t b = 0; b < blocks; ++b) {
    const auto start = static_cast<std::ptrdiff_t>(b * kSpringBlock);
    const auto push_run = [&](std::size_t slot, uint32_t flag) {
      for (std::size_t l = 0; l < kSpringBlock; ++l)
        rows.push_back(static_cast<uint32_t>(slot + l) | flag);
    };
    for (const Band& band : bands_) {
      const auto low = static_cast<std::ptrdiff_t>(band.low);
      const auto span = static_cast<std::ptrdiff_t>(band.high - band.low);
      if (start >= low && start - low < span)
        push_run(band.base + static_cast<std::size_t>(start - low), 0);
      // The first ends of this block's second ends: within a dead block of the band's ends.
      const std::ptrdiff_t window = start - static_cast<std::ptrdiff_t>(band.offset) - low;
      if (window > -static_cast<std::ptrdiff_t>(kSpringBlock) && window < span)
        push_run(static_cast<std::size_t>(static_cast<std::ptrdiff_t>(band.base) + window),
                 kSecondEnd);
    }
    std::size_t widest = 0;
    for (std::size_t i = b * kSpringBlock; i < std::min(particles, (b + 1) * kSpringBlock); ++i)
      widest = std::max(widest, incident[i].size());
    for (std::size_t k = 0; k < widest; ++k)
      for (std::size_t l = 0; l < kSpringBlock; ++l) {
        const std::size_t i = b * kSpringBlock + l;
        rows.push_back(i < particles && k < incident[i].size() ? incident[i][k] : 0u);
      }
    row_begin_.push_back(static_cast<uint32_t>(rows.size() / kSpringBlock));
  }
  entries_ = AlignedBuffer<uint32_t>(rows.size());
  std::copy(rows.begin(), rows.end(), entries_.data());
  row_in_order_.resize(row_begin_[blocks]);
  row_first_.resize(row_begin_[blocks]);
  for (uint32_t r = 0; r < row_begin_[blocks]; ++r) {
    const uint32_t* row = &entries_[std::size_t{r} * kSpringBlock];
    row_in_order_[r] = consecutive(row);
    row_first_[r] = row[0];
  }
}

namespace {

template <class Real, bool Damped>
void spring_block_portable(const Real* x, const Real* v, std::size_t stride, std::size_t block,
                           const uint32_t* first, const uint32_t* second, const Real* rest,
                           const Real* ks, const Real* kd, bool dead_slots, std::size_t slots,
                           Real* force) {
  for (std::size_t s = block * kSpringBlock; s < (block + 1) * kSpringBlock; ++s) {
    const std::size_t i = first[s], j = second[s];
    Real d[3], dv[3] = {0, 0, 0};
    for (std::size_t k = 0; k < 3; ++k) {
      d[k] = x[j + k * stride] - x[i + k * stride];
      if constexpr (Damped) dv[k] = v[j + k * stride] - v[i + k * stride];
    }
    Real law[3];
    spring_law(rest[s], ks[s], kd[s], kScalarInverseSqrtScale, law);
    const Real scale = spring_force_scale<Damped>(d[0], d[1], d[2], dv[0], dv[1], dv[2], law);
    const bool dead = dead_slots && ks[s] + kd[s] == Real(0);
    for (std::size_t k = 0; k < 3; ++k) force[k * slots + s] = dead ? Real(0) : scale * d[k];
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
                        uint32_t first, uint32_t second, const float (&law)[3], bool dead_slots,
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
  Floats lanes_law[3];
  if constexpr (OneLaw) {
    float one[3];
    spring_law(law[0], law[1], law[2], kLanesInverseSqrtScale, one);
    for (int t = 0; t < 3; ++t) lanes_law[t] = broadcast(one[t]);
  } else {
    spring_law(load_floats(arrays.rest + s), load_floats(arrays.ks + s), load_floats(arrays.kd + s),
               kLanesInverseSqrtScale, lanes_law);
  }
  const Floats scale = spring_force_scale<Damped>(d[0], d[1], d[2], dv[0], dv[1], dv[2], lanes_law);
  if (dead_slots) {
    const LaneMask live = not_equal(lanes_law[0] + lanes_law[2], zero_floats());
    for (std::size_t k = 0; k < 3; ++k)
      store_floats(force + k * slots + s, keep(live, scale * d[k]));
    return;
  }
  for (std::size_t k = 0; k < 3; ++k) store_floats(force + k * slots + s, scale * d[k]);
}

// definite_products' block from slot s, its ends in order or gathered, one law or a law per lane.
template <bool InOrder, bool OneLaw>
void definite_block_lanes(const float* x, const float* inverse_length, float c_x, float c_v,
                          const float* u, const float* inverse_mass, std::size_t stride,
                          std::size_t s, uint32_t first, uint32_t second, const float (&law)[3],
                          bool dead_slots, const SpringArrays& arrays, float* product,
                          std::size_t slots) {
  Floats d[3], u_first[3], u_second[3], mass_first, mass_second;
  if constexpr (InOrder) {
    mass_first = load_floats(inverse_mass + first);
    mass_second = load_floats(inverse_mass + second);
    for (std::size_t k = 0; k < 3; ++k) {
      d[k] = load_floats(x + k * stride + second) - load_floats(x + k * stride + first);
      u_first[k] = load_floats(u + k * stride + first);
      u_second[k] = load_floats(u + k * stride + second);
    }
  } else {
    const Indices i = load_indices(arrays.first + s), j = load_indices(arrays.second + s);
    mass_first = gather_floats(inverse_mass, i), mass_second = gather_floats(inverse_mass, j);
    for (std::size_t k = 0; k < 3; ++k) {
      d[k] = gather_floats(x + k * stride, j) - gather_floats(x + k * stride, i);
      u_first[k] = gather_floats(u + k * stride, i);
      u_second[k] = gather_floats(u + k * stride, j);
    }
  }
  const LaneMask first_active = greater(mass_first, zero_floats());
  const LaneMask second_active = greater(mass_second, zero_floats());
  Floats du[3];
  for (std::size_t k = 0; k < 3; ++k)
    du[k] = keep(second_active, u_second[k]) - keep(first_active, u_first[k]);
  Floats rest, ks, kd;
  if constexpr (OneLaw) {
    rest = broadcast(law[0]), ks = broadcast(law[1]), kd = broadcast(law[2]);
  } else {
    rest = load_floats(arrays.rest + s), ks = load_floats(arrays.ks + s);
    kd = load_floats(arrays.kd + s);
  }
  const Floats scale_x = broadcast(c_x);
  Floats across, along;
  definite_coefficients(load_floats(inverse_length + s), ks, ks * rest,
                        scale_x * ks + broadcast(c_v) * kd, scale_x, zero_floats(), across, along);
  along = along * (d[0] * du[0] + d[1] * du[1] + d[2] * du[2]);
  Floats out[3];
  for (std::size_t k = 0; k < 3; ++k) out[k] = across * du[k] + along * d[k];
  if (dead_slots) {
    const LaneMask live = not_equal(ks + kd, zero_floats());
    for (Floats& value : out) value = keep(live, value);
  }
  for (std::size_t k = 0; k < 3; ++k) store_floats(product + k * slots + s, out[k]);
}

template <bool Damped>
void spring_block_lanes(bool in_order, bool one_law, const float* x, const float* v,
                        std::size_t stride, std::size_t s, uint32_t first, uint32_t second,
                        const float (&law)[3], bool dead_slots, const SpringArrays& arrays,
                        float* force, std::size_t slots) {
  if (in_order && one_law)
    spring_block_lanes<Damped, true, true>(x, v, stride, s, first, second, law, dead_slots, arrays,
                                           force, slots);
  else if (in_order)
    spring_block_lanes<Damped, true, false>(x, v, stride, s, first, second, law, dead_slots, arrays,
                                            force, slots);
  else if (one_law)
    spring_block_lanes<Damped, false, true>(x, v, stride, s, first, second, law, dead_slots, arrays,
                                            force, slots);
  else
    spring_block_lanes<Damped, false, false>(x, v, stride, s, first, second, law, dead_slots,
                                             arrays, force, slots);
}
#endif

}  // namespace

template <class Real>
void SpringLanes<Real>::forces(const Real* x, const Real* v, std::size_t stride, std::size_t begin,
                               std::size_t end, Real* force) const {
  const bool damped = v != nullptr && damped_count_ > 0;
  for (std::size_t b = begin; b < end; ++b) {
    // Dead slots join particles that may not be finite: they write 0 whatever the state.
    if ((block_kind_[b] & kNoSpring) != 0) {
      for (std::size_t k = 0; k < 3; ++k)
        std::fill_n(force + k * slots() + b * kSpringBlock, kSpringBlock, Real(0));
      continue;
    }
    const bool dead_slots = (block_kind_[b] & kDeadSlots) != 0;
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
                                 block_second_[b], law, dead_slots, arrays, force, slots());
      else
        spring_block_lanes<false>(in_order, one_law, x, v, stride, s, block_first_[b],
                                  block_second_[b], law, dead_slots, arrays, force, slots());
      continue;
    }
#endif
    if (damped)
      spring_block_portable<Real, true>(x, v, stride, b, first_.data(), second_.data(),
                                        rest_.data(), ks_.data(), kd_.data(), dead_slots, slots(),
                                        force);
    else
      spring_block_portable<Real, false>(x, v, stride, b, first_.data(), second_.data(),
                                         rest_.data(), ks_.data(), kd_.data(), dead_slots, slots(),
                                         force);
  }
}

template <class Real>
void SpringLanes<Real>::inverse_lengths(const Real* x, std::size_t stride, std::size_t begin,
                                        std::size_t end, Real* inverse_length) const {
  for (std::size_t s = begin * kSpringBlock; s < end * kSpringBlock; ++s) {
    Real squared = 0;
    for (std::size_t k = 0; k < 3; ++k) {
      const Real d = x[k * stride + second_[s]] - x[k * stride + first_[s]];
      squared += d * d;
    }
    const bool dead = ks_[s] + kd_[s] == Real(0);
    inverse_length[s] = dead ? Real(0) : inverse_sqrt_or_zero(squared);
  }
}

template <class Real>
void SpringLanes<Real>::definite_products(const Real* x, const Real* inverse_length, Real c_x,
                                          Real c_v, const Real* u, const Real* inverse_mass,
                                          std::size_t stride, std::size_t begin, std::size_t end,
                                          Real* product) const {
  for (std::size_t b = begin; b < end; ++b) {
    if ((block_kind_[b] & kNoSpring) != 0) {
      for (std::size_t k = 0; k < 3; ++k)
        std::fill_n(product + k * slots() + b * kSpringBlock, kSpringBlock, Real(0));
      continue;
    }
    const bool dead_slots = (block_kind_[b] & kDeadSlots) != 0;
#if defined(CLOTHLAB_FLOAT_LANES)
    if constexpr (std::is_same_v<Real, float>) {
      const SpringArrays arrays{first_.data(), second_.data(), rest_.data(), ks_.data(),
                                kd_.data()};
      const float law[3] = {block_law_[b].rest, block_law_[b].ks, block_law_[b].kd};
      const bool in_order = (block_kind_[b] & kEndsInOrder) != 0;
      const bool one_law = (block_kind_[b] & kOneLaw) != 0;
      const auto block =
          in_order
              ? (one_law ? &definite_block_lanes<true, true> : &definite_block_lanes<true, false>)
              : (one_law ? &definite_block_lanes<false, true>
                         : &definite_block_lanes<false, false>);
      block(x, inverse_length, c_x, c_v, u, inverse_mass, stride, b * kSpringBlock, block_first_[b],
            block_second_[b], law, dead_slots, arrays, product, slots());
      continue;
    }
#endif
    for (std::size_t s = b * kSpringBlock; s < (b + 1) * kSpringBlock; ++s) {
      const std::size_t i = first_[s], j = second_[s];
      Real d[3], du[3];
      for (std::size_t k = 0; k < 3; ++k) {
        d[k] = x[k * stride + j] - x[k * stride + i];
        du[k] = (inverse_mass[j] > Real(0) ? u[k * stride + j] : Real(0)) -
                (inverse_mass[i] > Real(0) ? u[k * stride + i] : Real(0));
      }
      Real across, along;
      definite_coefficients(inverse_length[s], ks_[s], ks_[s] * rest_[s],
                            c_x * ks_[s] + c_v * kd_[s], c_x, Real(0), across, along);
      along = along * (d[0] * du[0] + d[1] * du[1] + d[2] * du[2]);
      const bool dead = dead_slots && ks_[s] + kd_[s] == Real(0);
      for (std::size_t k = 0; k < 3; ++k)
        product[k * slots() + s] = dead ? Real(0) : across * du[k] + along * d[k];
    }
  }
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
