#include "spring_lanes.hpp"

#include <algorithm>
#include <array>
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

constexpr uint32_t kAllLive = (1u << kSpringBlock) - 1;  // a block's live bits, none dead

bool consecutive(const uint32_t* values) {
  for (std::size_t l = 1; l < kSpringBlock; ++l)
    if (values[l] != values[0] + l) return false;
  return true;
}

}  // namespace

LaneBands::LaneBands(std::size_t particles, const std::vector<uint32_t>& ends, std::size_t arity,
                     uint32_t subtracted, std::size_t tile)
    : items_(ends.size() / arity), tile_(tile), ends_(arity) {
  const auto end_of = [&](std::size_t item, std::size_t e) { return ends[arity * item + e]; };
  // The offsets of an item's other ends from its first: its band's key.
  const auto offsets_of = [&](std::size_t item) {
    std::array<uint32_t, 2> offsets{};
    for (std::size_t e = 1; e < arity; ++e) offsets[e - 1] = end_of(item, e) - end_of(item, 0);
    return offsets;
  };
  std::vector<uint32_t> order(items_);
  std::iota(order.begin(), order.end(), 0u);
  std::stable_sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) {
    return offsets_of(a) != offsets_of(b) ? offsets_of(a) < offsets_of(b)
                                          : end_of(a, 0) < end_of(b, 0);
  });

  std::vector<uint32_t> slot_of(items_);
  std::vector<uint32_t> gathered;   // the items in no band, in order
  std::size_t next = kSpringBlock;  // after the leading dead block
  std::vector<std::array<uint32_t, 2>> band_offsets;
  for (std::size_t begin = 0, end = 0; begin < items_; begin = end) {
    const std::array<uint32_t, 2> offsets = offsets_of(order[begin]);
    bool distinct = true;
    for (end = begin + 1; end < items_ && offsets_of(order[end]) == offsets; ++end)
      distinct = distinct && end_of(order[end], 0) != end_of(order[end - 1], 0);
    const auto block = static_cast<uint32_t>(kSpringBlock);
    const uint32_t low = end_of(order[begin], 0) / block * block;
    const uint32_t high = (end_of(order[end - 1], 0) / block + 1) * block;
    if (!distinct || kBandShare * (end - begin) < high - low) {
      gathered.insert(gathered.end(), order.begin() + static_cast<std::ptrdiff_t>(begin),
                      order.begin() + static_cast<std::ptrdiff_t>(end));
      continue;
    }
    bands_.push_back({std::max(offsets[0], offsets[1]), low, high, next});
    band_offsets.push_back(offsets);
    dead_blocks_.push_back(static_cast<uint32_t>((next + high - low) / kSpringBlock));
    for (std::size_t k = begin; k < end; ++k)
      slot_of[order[k]] = static_cast<uint32_t>(next + end_of(order[k], 0) - low);
    next += high - low + kSpringBlock;  // and a dead block after it
  }
  const std::size_t gathered_base = next;
  gathered_block_ = gathered_base / kSpringBlock;
  // A ring holds a tile's first ends and the band's reach before them.
  for (Band& band : bands_) {
    band.ring_base = ring_slots_;
    band.ring_blocks = tile_ + (std::size_t{band.reach} + kSpringBlock - 1) / kSpringBlock;
    ring_slots_ += (band.ring_blocks + 1) * kSpringBlock;
  }
  dead_blocks_.push_back(0);
  for (std::size_t k = 0; k < gathered.size(); ++k)
    slot_of[gathered[k]] = static_cast<uint32_t>(gathered_base + k);

  const std::size_t slots =
      gathered_base + (gathered.size() + kSpringBlock - 1) / kSpringBlock * kSpringBlock;
  for (auto& end : ends_) end = AlignedBuffer<uint32_t>(slots);  // zeroed: particle 0
  item_in_.assign(slots, static_cast<uint32_t>(items_));
  // A band's dead slots join its own particles where they exist, so its blocks stay in order.
  for (std::size_t k = 0; k < bands_.size(); ++k) {
    const Band& band = bands_[k];
    for (uint32_t i = band.low; i < band.high && std::size_t{i} + band.reach < particles; ++i) {
      ends_[0][band.base + i - band.low] = i;
      for (std::size_t e = 1; e < arity; ++e)
        ends_[e][band.base + i - band.low] = i + band_offsets[k][e - 1];
    }
  }
  for (std::size_t item = 0; item < items_; ++item) {
    const std::size_t s = slot_of[item];
    for (std::size_t e = 0; e < arity; ++e) ends_[e][s] = end_of(item, e);
    item_in_[s] = static_cast<uint32_t>(item);
  }
  for (std::size_t b = 0; b < slots / kSpringBlock; ++b) {
    bool in_order = true;
    for (const auto& end : ends_) in_order = in_order && consecutive(&end[b * kSpringBlock]);
    in_order_.push_back(in_order);
  }

  // Each particle's gathered entries, ascending by slot.
  const std::size_t blocks = (particles + kSpringBlock - 1) / kSpringBlock;
  std::vector<std::vector<uint32_t>> incident(particles);
  for (uint32_t item : gathered)
    for (std::size_t e = 0; e < arity; ++e)
      incident[end_of(item, e)].push_back(slot_of[item] |
                                          ((subtracted >> e & 1u) != 0 ? kSubtract : 0u));
  for (auto& entries : incident)
    std::sort(entries.begin(), entries.end(),
              [](uint32_t a, uint32_t b) { return (a & ~kSubtract) < (b & ~kSubtract); });
  // Per particle block: each band's rows (the block's particles as each of the band's ends,
  // where the band reaches them), then its gathered rows.
  std::vector<uint32_t> rows;
  row_begin_.assign(1, 0);
  for (std::size_t b = 0; b < blocks; ++b) {
    const auto start = static_cast<std::ptrdiff_t>(b * kSpringBlock);
    const auto push_run = [&](std::size_t slot, uint32_t flag) {
      for (std::size_t l = 0; l < kSpringBlock; ++l)
        rows.push_back(static_cast<uint32_t>(slot + l) | flag);
    };
    for (std::size_t k = 0; k < bands_.size(); ++k) {
      const Band& band = bands_[k];
      const auto low = static_cast<std::ptrdiff_t>(band.low);
      const auto span = static_cast<std::ptrdiff_t>(band.high - band.low);
      for (std::size_t e = 0; e < arity; ++e) {
        // The first ends of this block's particles as end e: within a dead block of the band's.
        const uint32_t offset = e == 0 ? 0 : band_offsets[k][e - 1];
        const std::ptrdiff_t window = start - static_cast<std::ptrdiff_t>(offset) - low;
        if (window > -static_cast<std::ptrdiff_t>(kSpringBlock) && window < span) {
          const uint32_t flag = (subtracted >> e & 1u) != 0 ? kSubtract : 0u;
          push_run(static_cast<std::size_t>(static_cast<std::ptrdiff_t>(band.base) + window), flag);
          const auto ring = static_cast<std::ptrdiff_t>(band.ring_blocks * kSpringBlock);
          const std::ptrdiff_t first_end = window + low;
          row_ring_.push_back(
              static_cast<uint32_t>(band.ring_base +
                                    static_cast<std::size_t>((first_end % ring + ring) % ring)) |
              flag);
        }
      }
    }
    std::size_t widest = 0;
    for (std::size_t i = b * kSpringBlock; i < std::min(particles, (b + 1) * kSpringBlock); ++i)
      widest = std::max(widest, incident[i].size());
    row_ring_.insert(row_ring_.end(), widest, kGatheredRow);
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

template <class Real>
void LaneBands::sum_incident(const Real* per_slot, const Real* ring, std::size_t block,
                             Real (&sum)[3][kSpringBlock]) const {
  const std::size_t stride = slots();
#if defined(CLOTHLAB_FLOAT_LANES)
  if constexpr (std::is_same_v<Real, float>) {
    Floats total[3] = {load_floats(sum[0]), load_floats(sum[1]), load_floats(sum[2])};
    for (uint32_t r = row_begin_[block]; r < row_begin_[block + 1]; ++r) {
      if (ring != nullptr && row_ring_[r] != kGatheredRow) {
        const std::size_t slot = row_ring_[r] & ~kSubtract;
        const bool subtract = (row_ring_[r] & kSubtract) != 0;
        for (std::size_t k = 0; k < 3; ++k) {
          const Floats value = load_floats(ring + k * ring_slots_ + slot);
          total[k] = subtract ? total[k] - value : total[k] + value;
        }
      } else if (row_in_order_[r]) {
        const std::size_t slot = row_first_[r] & ~kSubtract;
        const bool subtract = (row_first_[r] & kSubtract) != 0;
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
  for (uint32_t r = row_begin_[block]; r < row_begin_[block + 1]; ++r) {
    const uint32_t* row = &entries_[std::size_t{r} * kSpringBlock];
    const bool in_ring = ring != nullptr && row_ring_[r] != kGatheredRow;
    const Real* values = in_ring ? ring : per_slot;
    const std::size_t values_stride = in_ring ? ring_slots_ : stride;
    for (std::size_t l = 0; l < kSpringBlock; ++l) {
      const uint32_t entry = in_ring ? row_ring_[r] + static_cast<uint32_t>(l) : row[l];
      const std::size_t slot = entry & ~kSubtract;
      const bool subtract = (entry & kSubtract) != 0;
      for (std::size_t k = 0; k < 3; ++k) {
        const Real value = values[k * values_stride + slot];
        sum[k][l] = subtract ? sum[k][l] - value : sum[k][l] + value;
      }
    }
  }
}

template void LaneBands::sum_incident(const float*, const float*, std::size_t,
                                      float (&)[3][kSpringBlock]) const;
template void LaneBands::sum_incident(const double*, const double*, std::size_t,
                                      double (&)[3][kSpringBlock]) const;

template <class Real>
SpringLanes<Real>::SpringLanes(const ClothModel& model, bool damped, std::size_t tile)
    : layout_(
          model.particle_count,
          [&] {
            std::vector<uint32_t> ends(2 * model.spring_count());
            for (std::size_t k = 0; k < model.spring_count(); ++k) {
              ends[2 * k] = model.first[k];
              ends[2 * k + 1] = model.second[k];
            }
            return ends;
          }(),
          2, 2u, tile),  // the second end subtracts
      first_(layout_.ends(0)),
      second_(layout_.ends(1)),
      damped_(damped) {
  const std::size_t slots = layout_.slots();
  rest_ = AlignedBuffer<Real>(slots);  // zeroed: every slot dead (law 0)
  ks_ = AlignedBuffer<Real>(slots);
  kd_ = AlignedBuffer<Real>(slots);
  for (std::size_t s = 0; s < slots; ++s) {
    const std::size_t spring = layout_.item_in(s);
    if (spring == layout_.items()) continue;
    rest_[s] = static_cast<Real>(model.rest_length[spring]);
    ks_[s] = static_cast<Real>(model.ks[spring]);
    const bool has_damping = damped && model.kd[spring] > 0.0;
    kd_[s] = has_damping ? static_cast<Real>(model.kd[spring]) : Real(0);
    damped_count_ += has_damping;
  }
  for (std::size_t b = 0; b < slots / kSpringBlock; ++b) {
    const std::size_t s = b * kSpringBlock;
    uint32_t live = 0;
    for (std::size_t l = 0; l < kSpringBlock; ++l)
      if (layout_.item_in(s + l) != layout_.items()) live |= 1u << l;
    // One law: every live lane's is the first live lane's (the dead lanes are masked).
    const std::size_t lead = live == 0 ? s : s + static_cast<std::size_t>(__builtin_ctz(live));
    bool one_stiffness = true, one_rest = true;
    for (std::size_t l = 0; l < kSpringBlock; ++l) {
      if ((live >> l & 1u) == 0) continue;
      one_stiffness = one_stiffness && ks_[s + l] == ks_[lead] && kd_[s + l] == kd_[lead];
      one_rest = one_rest && rest_[s + l] == rest_[lead];
    }
    const bool one_law = one_stiffness && one_rest;
    block_kind_.push_back(static_cast<uint8_t>(
        (layout_.ends_in_order(b) ? kEndsInOrder : 0) | (one_law ? kOneLaw : 0) |
        (one_stiffness && !one_law ? kOneStiffness : 0) | (live == kAllLive ? 0 : kDeadSlots) |
        (live != 0 ? 0 : kNoSpring)));
    block_live_.push_back(live);
    block_first_.push_back(first_[s]);
    block_second_.push_back(second_[s]);
    block_law_.push_back({rest_[lead], ks_[lead], kd_[lead]});
  }
  std::size_t live_slots = 0;
  for (uint32_t live : block_live_)
    live_slots += static_cast<std::size_t>(__builtin_popcount(live));
  packed_rest_ = AlignedBuffer<Real>(live_slots);
  packed_ks_ = AlignedBuffer<Real>(live_slots);
  packed_kd_ = AlignedBuffer<Real>(live_slots);
  std::size_t next = 0;
  for (std::size_t b = 0; b < block_live_.size(); ++b) {
    block_packed_.push_back(static_cast<uint32_t>(next));
    for (std::size_t l = 0; l < kSpringBlock; ++l) {
      if ((block_live_[b] >> l & 1u) == 0) continue;
      const std::size_t s = b * kSpringBlock + l;
      packed_rest_[next] = rest_[s], packed_ks_[next] = ks_[s], packed_kd_[next] = kd_[s];
      ++next;
    }
  }
}

namespace {

template <class Real, bool Damped>
void spring_block_portable(const Real* x, const Real* v, std::size_t stride, std::size_t block,
                           const uint32_t* first, const uint32_t* second, const Real* rest,
                           const Real* ks, const Real* kd, bool dead_slots, Real* force,
                           std::size_t force_stride) {
  for (std::size_t s = block * kSpringBlock, l = 0; l < kSpringBlock; ++s, ++l) {
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
    for (std::size_t k = 0; k < 3; ++k) force[k * force_stride + l] = dead ? Real(0) : scale * d[k];
  }
}

#if defined(CLOTHLAB_FLOAT_LANES)
}  // namespace

// The arrays a block reads where its ends are not in order or its lanes' laws differ (outside
// the anonymous namespace: the members' lambdas capture it).
struct SpringArrays {
  const uint32_t* first;
  const uint32_t* second;
  // The laws by slot; with expand loads, packed (SpringLanes::packed_rest_ and the others).
  const float* rest;
  const float* ks;
  const float* kd;
};

namespace {

// A block's law values on its lanes (0 in its dead lanes): from slot s, or, with expand loads,
// its live lanes' from `packed` in the packed arrays, so dead slots cost no memory traffic.
inline Floats law_floats(const float* values, std::size_t s, std::size_t packed, uint32_t live) {
#if defined(CLOTHLAB_EXPAND_LOADS)
  (void)s;
  return expand_floats(lanes_of_bits(live), values + packed);
#else
  (void)packed, (void)live;
  return load_floats(values + s);
#endif
}

// How a block's live lanes share their law (rest, ks, kd): not at all (each lane's loaded), ks and
// kd alone (broadcast, the rest lengths loaded), or the whole law (broadcast).
enum class LawShare { kNone, kStiffness, kAll };

// The block's law on the lanes, as spring_law gives it per lane: law the lead lane's.
template <LawShare Share>
void block_law_lanes(const SpringArrays& arrays, std::size_t s, std::size_t packed, uint32_t live,
                     const float (&law)[3], Floats (&lanes_law)[3]) {
  if constexpr (Share == LawShare::kAll) {
    float one[3];
    spring_law(law[0], law[1], law[2], kLanesInverseSqrtScale, one);
    for (int t = 0; t < 3; ++t) lanes_law[t] = broadcast(one[t]);
  } else if constexpr (Share == LawShare::kStiffness) {
    spring_law(law_floats(arrays.rest, s, packed, live), broadcast(law[1]), broadcast(law[2]),
               kLanesInverseSqrtScale, lanes_law);
  } else {
    spring_law(law_floats(arrays.rest, s, packed, live), law_floats(arrays.ks, s, packed, live),
               law_floats(arrays.kd, s, packed, live), kLanesInverseSqrtScale, lanes_law);
  }
}

// The block of springs from slot s: ends in order (runs from particles first and second) or
// gathered by the lanes' indices; its law shared as Share says.
template <bool Damped, bool InOrder, LawShare Share>
void spring_block_lanes(const float* x, const float* v, std::size_t stride, std::size_t s,
                        uint32_t first, uint32_t second, const float (&law)[3], uint32_t live,
                        std::size_t packed, const SpringArrays& arrays, float* force,
                        std::size_t force_stride) {
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
  block_law_lanes<Share>(arrays, s, packed, live, law, lanes_law);
  const Floats scale = spring_force_scale<Damped>(d[0], d[1], d[2], dv[0], dv[1], dv[2], lanes_law);
  if (live != kAllLive) {
    const LaneMask lanes = lanes_of_bits(live);
    for (std::size_t k = 0; k < 3; ++k)
      store_floats(force + k * force_stride, keep(lanes, scale * d[k]));
    return;
  }
  for (std::size_t k = 0; k < 3; ++k) store_floats(force + k * force_stride, scale * d[k]);
}

// definite_products' block from slot s, its ends in order or gathered, its law shared as Share
// says.
template <bool InOrder, LawShare Share>
void definite_block_lanes(const float* x, const float* inverse_length, float c_x, float c_v,
                          const float* u, const float* inverse_mass, std::size_t stride,
                          std::size_t s, uint32_t first, uint32_t second, const float (&law)[3],
                          uint32_t live, std::size_t packed, const SpringArrays& arrays,
                          float* product, std::size_t product_stride) {
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
  if constexpr (Share == LawShare::kAll) {
    rest = broadcast(law[0]), ks = broadcast(law[1]), kd = broadcast(law[2]);
  } else if constexpr (Share == LawShare::kStiffness) {
    rest = law_floats(arrays.rest, s, packed, live), ks = broadcast(law[1]);
    kd = broadcast(law[2]);
  } else {
    rest = law_floats(arrays.rest, s, packed, live), ks = law_floats(arrays.ks, s, packed, live);
    kd = law_floats(arrays.kd, s, packed, live);
  }
  const Floats scale_x = broadcast(c_x);
  Floats across, along;
  definite_coefficients(load_floats(inverse_length + s), ks, ks * rest,
                        scale_x * ks + broadcast(c_v) * kd, scale_x, zero_floats(), across, along);
  along = along * (d[0] * du[0] + d[1] * du[1] + d[2] * du[2]);
  Floats out[3];
  for (std::size_t k = 0; k < 3; ++k) out[k] = across * du[k] + along * d[k];
  if (live != kAllLive) {
    const LaneMask lanes = lanes_of_bits(live);
    for (Floats& value : out) value = keep(lanes, value);
  }
  for (std::size_t k = 0; k < 3; ++k) store_floats(product + k * product_stride, out[k]);
}

// Calls block(InOrder, Share) with the block's kind as compile-time constants.
template <class Block>
void with_block_kind(bool in_order, bool one_law, bool one_stiffness, const Block& block) {
  const auto with_share = [&](auto ends_in_order) {
    using All = std::integral_constant<LawShare, LawShare::kAll>;
    using Stiffness = std::integral_constant<LawShare, LawShare::kStiffness>;
    using None = std::integral_constant<LawShare, LawShare::kNone>;
    if (one_law)
      block(ends_in_order, All{});
    else if (one_stiffness)
      block(ends_in_order, Stiffness{});
    else
      block(ends_in_order, None{});
  };
  if (in_order)
    with_share(std::true_type{});
  else
    with_share(std::false_type{});
}
#endif

}  // namespace

template <class Real>
void SpringLanes<Real>::forces(const Real* x, const Real* v, std::size_t stride, std::size_t begin,
                               std::size_t end, Real* force, std::size_t force_stride) const {
  const bool damped = v != nullptr && damped_count_ > 0;
  for (std::size_t b = begin; b < end; ++b) {
    Real* out = force + (b - begin) * kSpringBlock;
    // Dead slots join particles that may not be finite: they write 0 whatever the state.
    if ((block_kind_[b] & kNoSpring) != 0) {
      for (std::size_t k = 0; k < 3; ++k)
        std::fill_n(out + k * force_stride, kSpringBlock, Real(0));
      continue;
    }
    const bool dead_slots = (block_kind_[b] & kDeadSlots) != 0;
#if defined(CLOTHLAB_FLOAT_LANES)
    if constexpr (std::is_same_v<Real, float>) {
#if defined(CLOTHLAB_EXPAND_LOADS)
      const SpringArrays arrays{first_, second_, packed_rest_.data(), packed_ks_.data(),
                                packed_kd_.data()};
#else
      const SpringArrays arrays{first_, second_, rest_.data(), ks_.data(), kd_.data()};
#endif
      const float law[3] = {block_law_[b].rest, block_law_[b].ks, block_law_[b].kd};
      const bool in_order = (block_kind_[b] & kEndsInOrder) != 0;
      const std::size_t s = b * kSpringBlock;
      const bool one_law = (block_kind_[b] & kOneLaw) != 0;
      const bool one_stiffness = (block_kind_[b] & kOneStiffness) != 0;
      with_block_kind(in_order, one_law, one_stiffness, [&](auto ends_in_order, auto shared) {
        if (damped)
          spring_block_lanes<true, ends_in_order(), shared()>(
              x, v, stride, s, block_first_[b], block_second_[b], law, block_live_[b],
              block_packed_[b], arrays, out, force_stride);
        else
          spring_block_lanes<false, ends_in_order(), shared()>(
              x, v, stride, s, block_first_[b], block_second_[b], law, block_live_[b],
              block_packed_[b], arrays, out, force_stride);
      });
      continue;
    }
#endif
    if (damped)
      spring_block_portable<Real, true>(x, v, stride, b, first_, second_, rest_.data(), ks_.data(),
                                        kd_.data(), dead_slots, out, force_stride);
    else
      spring_block_portable<Real, false>(x, v, stride, b, first_, second_, rest_.data(), ks_.data(),
                                         kd_.data(), dead_slots, out, force_stride);
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
                                          Real* product, std::size_t product_stride) const {
  for (std::size_t b = begin; b < end; ++b) {
    Real* out = product + (b - begin) * kSpringBlock;
    if ((block_kind_[b] & kNoSpring) != 0) {
      for (std::size_t k = 0; k < 3; ++k)
        std::fill_n(out + k * product_stride, kSpringBlock, Real(0));
      continue;
    }
    const bool dead_slots = (block_kind_[b] & kDeadSlots) != 0;
#if defined(CLOTHLAB_FLOAT_LANES)
    if constexpr (std::is_same_v<Real, float>) {
#if defined(CLOTHLAB_EXPAND_LOADS)
      const SpringArrays arrays{first_, second_, packed_rest_.data(), packed_ks_.data(),
                                packed_kd_.data()};
#else
      const SpringArrays arrays{first_, second_, rest_.data(), ks_.data(), kd_.data()};
#endif
      const float law[3] = {block_law_[b].rest, block_law_[b].ks, block_law_[b].kd};
      const bool in_order = (block_kind_[b] & kEndsInOrder) != 0;
      const bool one_law = (block_kind_[b] & kOneLaw) != 0;
      const bool one_stiffness = (block_kind_[b] & kOneStiffness) != 0;
      with_block_kind(in_order, one_law, one_stiffness, [&](auto ends_in_order, auto shared) {
        definite_block_lanes<ends_in_order(), shared()>(
            x, inverse_length, c_x, c_v, u, inverse_mass, stride, b * kSpringBlock, block_first_[b],
            block_second_[b], law, block_live_[b], block_packed_[b], arrays, out, product_stride);
      });
      continue;
    }
#endif
    for (std::size_t s = b * kSpringBlock, l = 0; l < kSpringBlock; ++s, ++l) {
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
        out[k * product_stride + l] = dead ? Real(0) : across * du[k] + along * d[k];
    }
  }
}

template class SpringLanes<float>;
template class SpringLanes<double>;

}  // namespace clothlab::detail::inline CLOTHLAB_SIMD_NAMESPACE
