#include "spring_lanes.hpp"

#include <algorithm>
#include <array>
#include <iterator>
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

// Chosen bands (head of spring_lanes.hpp): a run of items is a candidate where it is large but
// fills under kChosenFill of its slots; a chosen band is formed where it fills at least that.
constexpr std::size_t kChosenMinimum = 4 * kSpringBlock;  // items of a candidate run
constexpr double kChosenFill = 0.75;
constexpr std::size_t kChosenCandidates = 12;  // the largest candidate runs, whose quads are tried
constexpr std::size_t kMostChosenBands = 4;

// A chosen band: its corners (ascending, the first 0) and its items by anchor, ascending.
struct ChosenLayout {
  std::array<uint32_t, 4> corner;
  std::vector<std::pair<uint32_t, uint32_t>> slots;  // (anchor, item)
};

uint32_t span_of(uint32_t low, uint32_t high) {
  const auto block = static_cast<uint32_t>(kSpringBlock);
  return (high / block + 1) * block - low / block * block;
}

// Takes chosen bands' items out of runs (items of `arity` ends, the smallest first, end e of item
// k at ends[arity * k + e]; each run's items share their other ends' offsets from the first and
// are ordered by first end). A band is a quad (0, u, w, u + w), u < w: for springs, one whose
// diagonals are two candidate runs' offsets (w - u and w + u); for triangles, one that holds a
// candidate run's three corners. It takes the items of every candidate run that fit on its
// corners, each item the lowest free anchor that puts all its ends on corners. The band that
// takes the most items goes first, where it fills enough of its slots.
std::vector<ChosenLayout> choose_bands(std::size_t particles, std::size_t arity,
                                       const std::vector<uint32_t>& ends,
                                       std::vector<std::vector<uint32_t>>& runs) {
  const auto end_of = [&](uint32_t item, std::size_t e) { return ends[arity * item + e]; };
  std::vector<ChosenLayout> chosen;
  std::vector<uint8_t> occupied(particles, 0);
  std::vector<uint32_t> touched;
  while (chosen.size() < kMostChosenBands) {
    std::vector<std::size_t> candidates;
    for (std::size_t r = 0; r < runs.size(); ++r) {
      const std::vector<uint32_t>& run = runs[r];
      if (run.size() < kChosenMinimum) continue;
      const uint32_t span = span_of(end_of(run.front(), 0), end_of(run.back(), 0));
      if (static_cast<double>(run.size()) < kChosenFill * span) candidates.push_back(r);
    }
    std::stable_sort(candidates.begin(), candidates.end(),
                     [&](std::size_t a, std::size_t b) { return runs[a].size() > runs[b].size(); });
    candidates.resize(std::min(candidates.size(), kChosenCandidates));
    std::vector<std::array<uint32_t, 2>> quads;  // (u, w)
    const auto add_quad = [&](uint32_t u, uint32_t w) {
      if (u > w) std::swap(u, w);
      const std::array<uint32_t, 2> quad{u, w};
      if (u != 0 && u != w && std::find(quads.begin(), quads.end(), quad) == quads.end())
        quads.push_back(quad);
    };
    for (std::size_t p : candidates) {
      const uint32_t first = end_of(runs[p][0], 0);
      if (arity == 2) {
        for (std::size_t q : candidates) {
          const uint32_t a = end_of(runs[p][0], 1) - first,
                         b = end_of(runs[q][0], 1) - end_of(runs[q][0], 0);
          if (a < b && (a + b) % 2 == 0) add_quad((b - a) / 2, (a + b) / 2);
        }
      } else {
        const uint32_t s1 = std::min(end_of(runs[p][0], 1), end_of(runs[p][0], 2)) - first;
        const uint32_t s2 = std::max(end_of(runs[p][0], 1), end_of(runs[p][0], 2)) - first;
        add_quad(s1, s2), add_quad(s1, s2 - s1), add_quad(s2 - s1, s2);
      }
    }
    ChosenLayout best{};
    std::vector<std::size_t> best_members;
    for (const auto& [u, w] : quads) {
      const std::array<uint32_t, 4> corner{0, u, w, u + w};
      // Whether the item's ends lie on corners with its first at corner f.
      const auto fits = [&](uint32_t item, std::size_t f) {
        for (std::size_t e = 1; e < arity; ++e)
          if (std::find(corner.begin(), corner.end(),
                        corner[f] + end_of(item, e) - end_of(item, 0)) == corner.end())
            return false;
        return true;
      };
      const auto choices = [&](uint32_t item) {
        return int{fits(item, 0)} + int{fits(item, 1)} + int{fits(item, 2)};
      };
      // A run's items share their choices.
      std::vector<std::size_t> members;
      std::size_t total = 0;
      for (std::size_t c : candidates)
        if (choices(runs[c][0]) != 0) members.push_back(c), total += runs[c].size();
      if (total <= best.slots.size()) continue;
      // By first end; of one first end, those with fewer anchors to take first (the runs merged
      // in that order, each ordered by first end).
      std::stable_sort(members.begin(), members.end(), [&](std::size_t a, std::size_t b) {
        return choices(runs[a][0]) < choices(runs[b][0]);
      });
      std::vector<uint32_t> items, merged;
      const auto by_first_end = [&](uint32_t x, uint32_t y) { return end_of(x, 0) < end_of(y, 0); };
      for (std::size_t c : members) {
        merged.clear();
        std::merge(items.begin(), items.end(), runs[c].begin(), runs[c].end(),
                   std::back_inserter(merged), by_first_end);
        items.swap(merged);
      }
      ChosenLayout layout{corner, {}};
      for (uint32_t item : items) {
        const uint32_t i = end_of(item, 0);
        // The corners the first end may take, from the highest (the lowest anchor).
        for (std::size_t f = 3; f-- > 0;) {
          if (corner[f] > i || occupied[i - corner[f]] != 0 || !fits(item, f)) continue;
          occupied[i - corner[f]] = 1;
          touched.push_back(i - corner[f]);
          layout.slots.emplace_back(i - corner[f], item);
          break;
        }
      }
      for (uint32_t anchor : touched) occupied[anchor] = 0;
      touched.clear();
      if (layout.slots.size() <= best.slots.size()) continue;
      std::sort(layout.slots.begin(), layout.slots.end());
      const uint32_t span = span_of(layout.slots.front().first, layout.slots.back().first);
      if (static_cast<double>(layout.slots.size()) < kChosenFill * span) continue;
      best = std::move(layout);
      best_members = std::move(members);
    }
    if (best.slots.empty()) break;
    std::vector<uint8_t> taken(ends.size() / arity, 0);
    for (const auto& slot : best.slots) taken[slot.second] = 1;
    for (std::size_t c : best_members)
      std::erase_if(runs[c], [&](uint32_t item) { return taken[item] != 0; });
    chosen.push_back(std::move(best));
  }
  return chosen;
}

}  // namespace

LaneBands::LaneBands(std::size_t particles, const std::vector<uint32_t>& ends, std::size_t arity,
                     uint32_t subtracted, std::size_t tile)
    : items_(ends.size() / arity), tile_(tile), subtracted_(subtracted), ends_(arity) {
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

  // The runs of items of one set of offsets; the chosen bands take some of their items first.
  std::vector<std::vector<uint32_t>> runs;
  for (std::size_t begin = 0, end = 0; begin < items_; begin = end) {
    for (end = begin + 1; end < items_ && offsets_of(order[end]) == offsets_of(order[begin]); ++end)
      ;
    runs.emplace_back(order.begin() + static_cast<std::ptrdiff_t>(begin),
                      order.begin() + static_cast<std::ptrdiff_t>(end));
  }
  const std::vector<ChosenLayout> chosen = choose_bands(particles, arity, ends, runs);

  std::vector<uint32_t> slot_of(items_);
  std::vector<uint32_t> gathered;   // the items in no band, in order
  std::size_t next = kSpringBlock;  // after the leading dead block
  std::vector<std::array<uint32_t, 2>> band_offsets;
  const auto block = static_cast<uint32_t>(kSpringBlock);
  for (const std::vector<uint32_t>& run : runs) {
    if (run.empty()) continue;
    const std::array<uint32_t, 2> offsets = offsets_of(run[0]);
    bool distinct = true;
    for (std::size_t k = 1; k < run.size(); ++k)
      distinct = distinct && end_of(run[k], 0) != end_of(run[k - 1], 0);
    const uint32_t low = end_of(run.front(), 0) / block * block;
    const uint32_t high = (end_of(run.back(), 0) / block + 1) * block;
    if (!distinct || kBandShare * run.size() < high - low) {
      gathered.insert(gathered.end(), run.begin(), run.end());
      continue;
    }
    bands_.push_back({std::max(offsets[0], offsets[1]), low, high, next});
    band_offsets.push_back(offsets);
    dead_blocks_.push_back(static_cast<uint32_t>((next + high - low) / kSpringBlock));
    for (uint32_t item : run) slot_of[item] = static_cast<uint32_t>(next + end_of(item, 0) - low);
    next += high - low + kSpringBlock;  // and a dead block after it
  }
  for (const ChosenLayout& layout : chosen) {
    const uint32_t low = layout.slots.front().first / block * block;
    const uint32_t high = (layout.slots.back().first / block + 1) * block;
    Band band{layout.corner[3], low, high, next};
    band.chosen = true;
    band.corner = layout.corner;
    bands_.push_back(band);
    band_offsets.push_back({});
    dead_blocks_.push_back(static_cast<uint32_t>((next + high - low) / kSpringBlock));
    for (const auto& [anchor, item] : layout.slots)
      slot_of[item] = static_cast<uint32_t>(next + anchor - low);
    next += high - low + kSpringBlock;
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
    if (band.chosen) continue;
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
  corner_of_.assign(slots, 0);
  chosen_of_.assign(slots / kSpringBlock, 0);
  chosen_corners_.assign(bands_.size(), {});
  for (std::size_t k = 0; k < bands_.size(); ++k) {
    const Band& band = bands_[k];
    if (!band.chosen) continue;
    for (std::size_t c = 0; c < 4; ++c)
      chosen_corners_[k][c] = band.low - static_cast<uint32_t>(band.base) + band.corner[c];
    for (std::size_t s = band.base; s < band.base + band.high - band.low; ++s) {
      const uint32_t item = item_in_[s];
      if (item == items_) continue;
      const uint32_t anchor = band.low + static_cast<uint32_t>(s - band.base);
      for (std::size_t e = 0; e < arity; ++e) {
        const auto at = std::find(band.corner.begin(), band.corner.end(), end_of(item, e) - anchor);
        corner_of_[s] |= static_cast<uint8_t>((at - band.corner.begin()) << (2 * e));
      }
    }
    // A block loads its corners in order where the last lane's last corner is a particle.
    for (std::size_t b = band.base / kSpringBlock;
         b < (band.base + band.high - band.low) / kSpringBlock; ++b)
      if (band.low + (b * kSpringBlock - band.base) + kSpringBlock - 1 + band.corner[3] < particles)
        chosen_of_[b] = static_cast<uint16_t>(k + 1);
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
  std::vector<uint32_t> choice, chosen_first;  // per row: row_choice_, a chosen row's first slot
  row_begin_.assign(1, 0);
  row_chosen_.clear();
  row_gathered_.clear();
  for (std::size_t b = 0; b < blocks; ++b) {
    const auto start = static_cast<std::ptrdiff_t>(b * kSpringBlock);
    const auto push_run = [&](std::size_t slot, uint32_t flag) {
      for (std::size_t l = 0; l < kSpringBlock; ++l)
        rows.push_back(static_cast<uint32_t>(slot + l) | flag);
    };
    for (std::size_t k = 0; k < bands_.size(); ++k) {
      const Band& band = bands_[k];
      if (band.chosen && row_chosen_.size() == b)
        row_chosen_.push_back(static_cast<uint32_t>(rows.size() / kSpringBlock));
      const auto low = static_cast<std::ptrdiff_t>(band.low);
      const auto span = static_cast<std::ptrdiff_t>(band.high - band.low);
      const auto ring = static_cast<std::ptrdiff_t>(band.ring_blocks * kSpringBlock);
      if (band.chosen) {
        // One row per corner: each lane adds (or subtracts) its slot where one of its item's
        // ends is there, else takes nothing.
        for (std::size_t c = 0; c < 4; ++c) {
          const std::ptrdiff_t window = start - static_cast<std::ptrdiff_t>(band.corner[c]) - low;
          if (window <= -static_cast<std::ptrdiff_t>(kSpringBlock) || window >= span) continue;
          const auto first_slot =
              static_cast<std::size_t>(static_cast<std::ptrdiff_t>(band.base) + window);
          uint32_t adds = 0, subtracts = 0;
          std::array<uint32_t, kSpringBlock> row{};
          for (std::size_t l = 0; l < kSpringBlock; ++l) {
            const std::size_t slot = first_slot + l;
            if (item_in_[slot] == items_) continue;
            for (std::size_t e = 0; e < arity; ++e) {
              if ((corner_of_[slot] >> (2 * e) & 3u) != c) continue;
              const bool subtract = (subtracted >> e & 1u) != 0;
              (subtract ? subtracts : adds) |= 1u << l;
              row[l] = static_cast<uint32_t>(slot) | (subtract ? kSubtract : 0u);
            }
          }
          if ((adds | subtracts) == 0) continue;
          rows.insert(rows.end(), row.begin(), row.end());
          const std::ptrdiff_t anchor = window + low;
          row_ring_.push_back(static_cast<uint32_t>(
              band.ring_base + static_cast<std::size_t>((anchor % ring + ring) % ring)));
          choice.push_back(adds | subtracts << kSpringBlock);
          chosen_first.push_back(static_cast<uint32_t>(first_slot));
        }
        continue;
      }
      for (std::size_t e = 0; e < arity; ++e) {
        // The first ends of this block's particles as end e: within a dead block of the band's.
        const uint32_t offset = e == 0 ? 0 : band_offsets[k][e - 1];
        const std::ptrdiff_t window = start - static_cast<std::ptrdiff_t>(offset) - low;
        if (window > -static_cast<std::ptrdiff_t>(kSpringBlock) && window < span) {
          const uint32_t flag = (subtracted >> e & 1u) != 0 ? kSubtract : 0u;
          push_run(static_cast<std::size_t>(static_cast<std::ptrdiff_t>(band.base) + window), flag);
          const std::ptrdiff_t first_end = window + low;
          row_ring_.push_back(
              static_cast<uint32_t>(band.ring_base +
                                    static_cast<std::size_t>((first_end % ring + ring) % ring)) |
              flag);
          choice.push_back(0);
          chosen_first.push_back(0);
        }
      }
    }
    if (row_chosen_.size() == b)
      row_chosen_.push_back(static_cast<uint32_t>(rows.size() / kSpringBlock));
    row_gathered_.push_back(static_cast<uint32_t>(rows.size() / kSpringBlock));
    std::size_t widest = 0;
    for (std::size_t i = b * kSpringBlock; i < std::min(particles, (b + 1) * kSpringBlock); ++i)
      widest = std::max(widest, incident[i].size());
    row_ring_.insert(row_ring_.end(), widest, kGatheredRow);
    choice.insert(choice.end(), widest, 0u);
    chosen_first.insert(chosen_first.end(), widest, 0u);
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
    row_in_order_[r] = choice[r] == 0 && consecutive(row);
    row_first_[r] = choice[r] == 0 ? row[0] : chosen_first[r];
  }
  row_choice_.resize(choice.size());
  using Bits = ChosenLanes<1>::Bits;
  for (std::size_t r = 0; r < choice.size(); ++r)
    row_choice_[r] = {static_cast<Bits>((choice[r] | choice[r] >> kSpringBlock) & kAllLive),
                      static_cast<Bits>(choice[r] >> kSpringBlock)};
}

template <std::size_t Ends>
bool LaneBands::chosen_lanes(std::size_t block, ChosenLanes<Ends>& lanes) const {
  if (chosen_of_[block] == 0) return false;
  lanes = ChosenLanes<Ends>{};
  lanes.band = static_cast<uint16_t>(chosen_of_[block] - 1u);
  using Bits = typename ChosenLanes<Ends>::Bits;
  for (std::size_t l = 0; l < kSpringBlock; ++l) {
    const std::size_t slot = block * kSpringBlock + l;
    if (item_in_[slot] == items_) continue;
    for (std::size_t e = 0; e < std::min(Ends, ends_.size()); ++e) {
      const uint32_t corner = corner_of_[slot] >> (2 * e) & 3u;
      lanes.low[e] = static_cast<Bits>(lanes.low[e] | (corner & 1u) << l);
      lanes.high[e] = static_cast<Bits>(lanes.high[e] | (corner >> 1) << l);
    }
  }
  return true;
}

template bool LaneBands::chosen_lanes(std::size_t, ChosenLanes<2>&) const;
template bool LaneBands::chosen_lanes(std::size_t, ChosenLanes<3>&) const;

template <class Real>
void LaneBands::sum_incident(const Real* per_slot, const Real* ring, std::size_t block,
                             Real (&sum)[3][kSpringBlock]) const {
  const std::size_t stride = slots();
#if defined(CLOTHLAB_FLOAT_LANES)
  if constexpr (std::is_same_v<Real, float>) {
    Floats total[3] = {load_floats(sum[0]), load_floats(sum[1]), load_floats(sum[2])};
    // Row r's slots in order from `values` (components `values_stride` apart), added or
    // subtracted as `at`'s top bit says, or per lane as its choice says.
    const auto add_in_order = [&](const float* values, std::size_t values_stride, uint32_t at) {
      values += at & ~kSubtract;
      if ((at & kSubtract) != 0) {
        for (std::size_t k = 0; k < 3; ++k)
          total[k] = total[k] - load_floats(values + k * values_stride);
      } else {
        for (std::size_t k = 0; k < 3; ++k)
          total[k] = total[k] + load_floats(values + k * values_stride);
      }
    };
    // A chosen row adds each live lane's value, negated where it subtracts: the same bits as
    // adding and subtracting each masked, as a sum that starts at +0 is never -0 (x + +0 = x).
    const auto add_chosen = [&](const float* values, std::size_t values_stride, uint32_t r,
                                auto any_subtracted) {
      const LaneMask live = lanes_of_bits(&row_choice_[r].live);
      [[maybe_unused]] const LaneMask subtracts = lanes_of_bits(&row_choice_[r].subtracts);
      for (std::size_t k = 0; k < 3; ++k) {
        Floats value = load_floats(values + k * values_stride);
        if constexpr (any_subtracted()) value = negated_where(subtracts, value);
        total[k] = total[k] + keep(live, value);
      }
    };
    uint32_t r = row_begin_[block];
    if (ring != nullptr) {  // the bands' rows from the ring, each kind in a loop of its own
      const std::size_t ring_stride = ring_slots_;
      for (const uint32_t chosen = row_chosen_[block]; r < chosen; ++r)
        add_in_order(ring, ring_stride, row_ring_[r]);
      const auto chosen_rows = [&](auto any_subtracted) {
        for (const uint32_t gathered = row_gathered_[block]; r < gathered; ++r)
          add_chosen(ring + row_ring_[r], ring_stride, r, any_subtracted);
      };
      if (subtracted_ != 0)
        chosen_rows(std::true_type{});
      else
        chosen_rows(std::false_type{});
    }
    for (; r < row_begin_[block + 1]; ++r) {
      if (row_choice_[r].any()) {
        add_chosen(per_slot + row_first_[r], stride, r, std::true_type{});
      } else if (row_in_order_[r]) {
        add_in_order(per_slot, stride, row_first_[r]);
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
      // A chosen row's lanes take their slots from the ring in order, where they take one.
      if (in_ring && row_choice_[r].any() && row[l] == 0) continue;
      const uint32_t entry =
          in_ring ? (row_ring_[r] + static_cast<uint32_t>(l)) | (row[l] & kSubtract) : row[l];
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
    bool one_stiffness = true, one_rest = true, two_stiffnesses = true;
    SecondStiffness second;
    for (std::size_t l = 0; l < kSpringBlock; ++l) {
      if ((live >> l & 1u) == 0) continue;
      const bool first_stiffness = ks_[s + l] == ks_[lead] && kd_[s + l] == kd_[lead];
      one_stiffness = one_stiffness && first_stiffness;
      one_rest = one_rest && rest_[s + l] == rest_[lead];
      if (first_stiffness) continue;
      if (second.lanes == 0) second.ks = ks_[s + l], second.kd = kd_[s + l];
      two_stiffnesses = two_stiffnesses && ks_[s + l] == second.ks && kd_[s + l] == second.kd;
      second.lanes |= 1u << l;
    }
    const bool one_law = one_stiffness && one_rest;
    two_stiffnesses = two_stiffnesses && !one_stiffness;
    ChosenLanes<2> ends;
    const bool chosen = !layout_.ends_in_order(b) && live != 0 && layout_.chosen_lanes(b, ends);
    block_extra_.push_back(static_cast<uint32_t>(chosen_.size()));
    if (chosen || two_stiffnesses) chosen_.push_back(ends), second_stiffness_.push_back(second);
    const auto kind = static_cast<uint8_t>(
        (layout_.ends_in_order(b) ? kEndsInOrder : 0) | (chosen ? kChosen : 0) |
        (one_law ? kOneLaw : 0) | (one_stiffness && !one_law ? kOneStiffness : 0) |
        (two_stiffnesses ? kTwoStiffnesses : 0) | (live == kAllLive ? 0 : kDeadSlots) |
        (live != 0 ? 0 : kNoSpring));
    // Whether the block continues its predecessor's run (BlockKind).
    bool follows = b > 0 && (block_kind_[b - 1] & ~kRunParity) == kind;
    if (follows && (kind & kEndsInOrder) != 0)
      follows = first_[s] == block_first_[b - 1] + kSpringBlock &&
                second_[s] == block_second_[b - 1] + kSpringBlock;
    if (follows && (kind & kChosen) == 0 && (kind & (kOneLaw | kOneStiffness)) != 0)
      follows = ks_[lead] == block_law_[b - 1].ks && kd_[lead] == block_law_[b - 1].kd &&
                ((kind & kOneLaw) == 0 || rest_[lead] == block_law_[b - 1].rest);
    const bool parity = b > 0 && ((block_kind_[b - 1] & kRunParity) != 0) == follows;
    block_kind_.push_back(static_cast<uint8_t>(kind | (parity ? kRunParity : 0)));
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

// A block's laws (outside the anonymous namespace, as SpringArrays) as its kind gives them: law its
// lead lane's; second, where it has two ks and kd, the other and its lanes.
struct BlockLaws {
  float law[3];
  float second_ks, second_kd;
  uint32_t second_lanes;
};

// The BlockKind bits block_runs reads (SpringLanes' enum is private; outside the
// anonymous namespace, as SpringArrays).
struct KindBits {
  uint8_t in_order, chosen, one_law, one_stiffness, two_stiffnesses, no_spring;
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

// Where a block's lanes read their two ends: lane 0's in order, the lanes' by index, or a chosen
// band's four corners in order, picked per lane.
enum class EndsAt { kGathered, kInOrder, kChosen };

template <EndsAt At>
class EndLanes {
 public:
  // chosen and corners (its band's LaneBands::chosen_corners) are read only where At is kChosen.
  EndLanes(const SpringArrays& arrays, std::size_t s, uint32_t first, uint32_t second,
           const ChosenLanes<2>* chosen, const std::array<uint32_t, 4>* corners)
      : first_(first), second_(second) {
    if constexpr (At == EndsAt::kGathered) {
      i_ = load_indices(arrays.first + s), j_ = load_indices(arrays.second + s);
    } else if constexpr (At == EndsAt::kChosen) {
      for (std::size_t c = 0; c < 4; ++c) at_[c] = static_cast<uint32_t>(s) + (*corners)[c];
      for (std::size_t e = 0; e < 2; ++e)
        low_[e] = lanes_of_bits(&chosen->low[e]), high_[e] = lanes_of_bits(&chosen->high[e]);
    }
  }
  // values (one per particle) at each lane's first and second end.
  void operator()(const float* values, Floats& at_first, Floats& at_second) const {
    if constexpr (At == EndsAt::kInOrder) {
      at_first = load_floats(values + first_), at_second = load_floats(values + second_);
    } else if constexpr (At == EndsAt::kGathered) {
      at_first = gather_floats(values, i_), at_second = gather_floats(values, j_);
    } else {
      Floats corner[4];
      for (std::size_t c = 0; c < 4; ++c) corner[c] = load_floats(values + at_[c]);
      // A spring's first end is never the last corner, its second never the first.
      at_first = select(high_[0], corner[2], select(low_[0], corner[1], corner[0]));
      at_second = select(high_[1], select(low_[1], corner[3], corner[2]), corner[1]);
    }
  }

 private:
  uint32_t first_, second_;
  Indices i_{}, j_{};
  std::array<uint32_t, 4> at_{};
  LaneMask low_[2] = {lanes_of_bits(0u), lanes_of_bits(0u)};
  LaneMask high_[2] = {lanes_of_bits(0u), lanes_of_bits(0u)};
};

// How a block's live lanes share their law (rest, ks, kd): not at all (each lane's loaded), two
// ks and kd (each broadcast, picked per lane; the rest lengths loaded), ks and kd alone
// (broadcast, the rest lengths loaded), or the whole law (broadcast).
enum class LawShare { kNone, kTwoStiffnesses, kStiffness, kAll };

// The block's rest, ks and kd on the lanes.
template <LawShare Share>
void block_law_values(const SpringArrays& arrays, std::size_t s, std::size_t packed, uint32_t live,
                      const BlockLaws& laws, Floats& rest, Floats& ks, Floats& kd) {
  if constexpr (Share == LawShare::kNone) {
    rest = law_floats(arrays.rest, s, packed, live), ks = law_floats(arrays.ks, s, packed, live);
    kd = law_floats(arrays.kd, s, packed, live);
    return;
  }
  ks = broadcast(laws.law[1]), kd = broadcast(laws.law[2]);
  if constexpr (Share == LawShare::kAll) {
    rest = broadcast(laws.law[0]);
    return;
  }
  rest = law_floats(arrays.rest, s, packed, live);
  if constexpr (Share == LawShare::kTwoStiffnesses) {
    const LaneMask second = lanes_of_bits(laws.second_lanes);
    ks = select(second, broadcast(laws.second_ks), ks);
    kd = select(second, broadcast(laws.second_kd), kd);
  }
}

// The block's law on the lanes, as spring_law gives it per lane.
template <LawShare Share>
void block_law_lanes(const SpringArrays& arrays, std::size_t s, std::size_t packed, uint32_t live,
                     const BlockLaws& laws, Floats (&lanes_law)[3]) {
  if constexpr (Share == LawShare::kAll) {
    float one[3];
    spring_law(laws.law[0], laws.law[1], laws.law[2], kLanesInverseSqrtScale, one);
    for (int t = 0; t < 3; ++t) lanes_law[t] = broadcast(one[t]);
  } else {
    Floats rest, ks, kd;
    block_law_values<Share>(arrays, s, packed, live, laws, rest, ks, kd);
    spring_law(rest, ks, kd, kLanesInverseSqrtScale, lanes_law);
  }
}

// The block of springs from slot s, its ends read as At says (EndLanes); its law shared as Share
// says.
template <bool Damped, EndsAt At, LawShare Share>
void spring_block_lanes(const float* x, const float* v, std::size_t stride, std::size_t s,
                        const EndLanes<At>& ends, const BlockLaws& laws, uint32_t live,
                        std::size_t packed, const SpringArrays& arrays, float* force,
                        std::size_t force_stride) {
  Floats d[3], dv[3] = {};
  for (std::size_t k = 0; k < 3; ++k) {
    Floats at_first, at_second;
    ends(x + k * stride, at_first, at_second);
    d[k] = at_second - at_first;
    if constexpr (Damped) {
      ends(v + k * stride, at_first, at_second);
      dv[k] = at_second - at_first;
    }
  }
  Floats lanes_law[3];
  block_law_lanes<Share>(arrays, s, packed, live, laws, lanes_law);
  const Floats scale = spring_force_scale<Damped>(d[0], d[1], d[2], dv[0], dv[1], dv[2], lanes_law);
  if (live != kAllLive) {
    const LaneMask lanes = lanes_of_bits(live);
    for (std::size_t k = 0; k < 3; ++k)
      store_floats(force + k * force_stride, keep(lanes, scale * d[k]));
    return;
  }
  for (std::size_t k = 0; k < 3; ++k) store_floats(force + k * force_stride, scale * d[k]);
}

// definite_products' block from slot s, its ends read as At says, its law shared as Share says.
template <EndsAt At, LawShare Share>
void definite_block_lanes(const float* x, const float* inverse_length, float c_x, float c_v,
                          const float* u, const float* inverse_mass, std::size_t stride,
                          std::size_t s, const EndLanes<At>& ends, const BlockLaws& laws,
                          uint32_t live, std::size_t packed, const SpringArrays& arrays,
                          float* product, std::size_t product_stride) {
  Floats d[3], u_first[3], u_second[3], mass_first, mass_second;
  ends(inverse_mass, mass_first, mass_second);
  for (std::size_t k = 0; k < 3; ++k) {
    Floats at_first, at_second;
    ends(x + k * stride, at_first, at_second);
    d[k] = at_second - at_first;
    ends(u + k * stride, u_first[k], u_second[k]);
  }
  const LaneMask first_active = greater(mass_first, zero_floats());
  const LaneMask second_active = greater(mass_second, zero_floats());
  Floats du[3];
  for (std::size_t k = 0; k < 3; ++k)
    du[k] = keep(second_active, u_second[k]) - keep(first_active, u_first[k]);
  Floats rest, ks, kd;
  block_law_values<Share>(arrays, s, packed, live, laws, rest, ks, kd);
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

// Calls block(At, Share) with the block's kind as compile-time constants.
template <class Block>
void with_block_kind(EndsAt at, LawShare share, const Block& block) {
  const auto with_share = [&](auto ends_in_order) {
    using All = std::integral_constant<LawShare, LawShare::kAll>;
    using Stiffness = std::integral_constant<LawShare, LawShare::kStiffness>;
    using Two = std::integral_constant<LawShare, LawShare::kTwoStiffnesses>;
    using None = std::integral_constant<LawShare, LawShare::kNone>;
    if (share == LawShare::kAll)
      block(ends_in_order, All{});
    else if (share == LawShare::kStiffness)
      block(ends_in_order, Stiffness{});
    else if (share == LawShare::kTwoStiffnesses)
      block(ends_in_order, Two{});
    else
      block(ends_in_order, None{});
  };
  if (at == EndsAt::kInOrder)
    with_share(std::integral_constant<EndsAt, EndsAt::kInOrder>{});
  else if (at == EndsAt::kChosen)
    with_share(std::integral_constant<EndsAt, EndsAt::kChosen>{});
  else
    with_share(std::integral_constant<EndsAt, EndsAt::kGathered>{});
}

// Where the block's kind says its ends are read.
inline EndsAt ends_at(uint8_t kind, uint8_t in_order, uint8_t chosen) {
  return (kind & in_order) != 0 ? EndsAt::kInOrder
                                : ((kind & chosen) != 0 ? EndsAt::kChosen : EndsAt::kGathered);
}

// How the block's kind says its lanes share their law.
inline LawShare law_share(uint8_t kind, uint8_t one_law, uint8_t one_stiffness,
                          uint8_t two_stiffnesses) {
  if ((kind & one_law) != 0) return LawShare::kAll;
  if ((kind & one_stiffness) != 0) return LawShare::kStiffness;
  return (kind & two_stiffnesses) != 0 ? LawShare::kTwoStiffnesses : LawShare::kNone;
}

// A block's laws as Share reads them: law its lead lane's (SpringLanes::BlockLaw), second()
// its SpringLanes::SecondStiffness, read only where it has two.
template <LawShare Share, class Law, class Second>
BlockLaws block_laws(const Law& law, const Second& second) {
  BlockLaws laws{{law.rest, law.ks, law.kd}, 0.0f, 0.0f, 0u};
  if constexpr (Share == LawShare::kTwoStiffnesses) {
    const auto& other = second();
    laws.second_ks = other.ks, laws.second_kd = other.kd, laws.second_lanes = other.lanes;
  }
  return laws;
}

// Calls run(At, Share, begin, end) on the runs of blocks [begin, end) of one kind (a band's
// blocks mostly share theirs), so a block's kind is dispatched once per run, and zero(b) on each
// block with no spring. Inlined by force, as each_block: GCC 12 leaves it out of line, under a
// name (of generic lambdas) that objdump cannot demangle, so check_simd_isolation.py cannot place
// it in its target.
template <class Run, class Zero>
[[gnu::always_inline]] inline void block_runs(const uint8_t* kind, std::size_t begin,
                                              std::size_t end, const KindBits& bits, const Run& run,
                                              const Zero& zero) {
  for (std::size_t b = begin; b < end;) {
    std::size_t run_end = b + 1;
    while (run_end < end && kind[run_end] == kind[b]) ++run_end;
    if ((kind[b] & bits.no_spring) != 0) {
      for (; b < run_end; ++b) zero(b);
      continue;
    }
    with_block_kind(ends_at(kind[b], bits.in_order, bits.chosen),
                    law_share(kind[b], bits.one_law, bits.one_stiffness, bits.two_stiffnesses),
                    [&](auto where, auto shared) { run(where, shared, b, run_end); });
    b = run_end;
  }
}
#endif

}  // namespace

template <class Real>
template <class Lanes, class Portable>
[[gnu::always_inline]] inline void SpringLanes<Real>::each_block(
    std::size_t begin, std::size_t end, Real* out, std::size_t out_stride,
    [[maybe_unused]] const Lanes& lanes, const Portable& portable) const {
  // Dead slots join particles that may not be finite: a block with no spring writes 0 whatever
  // the state.
  const auto zero = [&](std::size_t b) {
    Real* block_out = out + (b - begin) * kSpringBlock;
    for (std::size_t k = 0; k < 3; ++k)
      std::fill_n(block_out + k * out_stride, kSpringBlock, Real(0));
  };
#if defined(CLOTHLAB_FLOAT_LANES)
  if constexpr (std::is_same_v<Real, float>) {
#if defined(CLOTHLAB_EXPAND_LOADS)
    const SpringArrays arrays{first_, second_, packed_rest_.data(), packed_ks_.data(),
                              packed_kd_.data()};
#else
    const SpringArrays arrays{first_, second_, rest_.data(), ks_.data(), kd_.data()};
#endif
    const auto run = [&](auto where, auto shared, std::size_t from, std::size_t to) {
      // A run of chosen blocks lies in one band (a dead block follows each band): its corners
      // are looked up once.
      const std::array<uint32_t, 4>* corners = nullptr;
      if constexpr (where() == EndsAt::kChosen)
        corners = layout_.chosen_corners() + chosen_[block_extra_[from]].band;
      // The run's ends in order and, but for chosen blocks (whose registers are full), its one
      // law or stiffness are its first block's (BlockKind).
      constexpr bool in_order = where() == EndsAt::kInOrder;
      constexpr bool law_per_block =
          where() == EndsAt::kChosen || shared() == LawShare::kTwoStiffnesses;
      const uint32_t first = in_order ? block_first_[from] : 0u;
      const uint32_t second = in_order ? block_second_[from] : 0u;
      const BlockLaw& run_law = block_law_[from];
      for (std::size_t b = from; b < to; ++b) {
        const std::size_t s = b * kSpringBlock;
        const auto step = in_order ? static_cast<uint32_t>(s - from * kSpringBlock) : 0u;
        const EndLanes<where()> ends(arrays, s, first + step, second + step,
                                     chosen_.data() + block_extra_[b], corners);
        const BlockLaw& law = law_per_block ? block_law_[b] : run_law;
        const BlockLaws laws = block_laws<shared()>(
            law, [&]() -> const SecondStiffness& { return second_stiffness_[block_extra_[b]]; });
        lanes(where, shared, arrays, ends, laws, b, out + (b - begin) * kSpringBlock);
      }
    };
    const KindBits bits{kEndsInOrder, kChosen, kOneLaw, kOneStiffness, kTwoStiffnesses, kNoSpring};
    block_runs(block_kind_.data(), begin, end, bits, run, zero);
    return;
  }
#endif
  for (std::size_t b = begin; b < end; ++b) {
    if ((block_kind_[b] & kNoSpring) != 0)
      zero(b);
    else
      portable(b, (block_kind_[b] & kDeadSlots) != 0, out + (b - begin) * kSpringBlock);
  }
}

template <class Real>
void SpringLanes<Real>::forces(const Real* x, const Real* v, std::size_t stride, std::size_t begin,
                               std::size_t end, Real* force, std::size_t force_stride) const {
  const auto with_damping = [&](auto damped) {
    each_block(
        begin, end, force, force_stride,
        [&](auto where, auto shared, const auto& arrays, const auto& ends, const auto& laws,
            std::size_t b, float* out) {
          spring_block_lanes<damped(), where(), shared()>(x, v, stride, b * kSpringBlock, ends,
                                                          laws, block_live_[b], block_packed_[b],
                                                          arrays, out, force_stride);
        },
        [&](std::size_t b, bool dead_slots, Real* out) {
          spring_block_portable<Real, damped()>(x, v, stride, b, first_, second_, rest_.data(),
                                                ks_.data(), kd_.data(), dead_slots, out,
                                                force_stride);
        });
  };
  if (v != nullptr && damped_count_ > 0)
    with_damping(std::true_type{});
  else
    with_damping(std::false_type{});
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
  each_block(
      begin, end, product, product_stride,
      [&](auto where, auto shared, const auto& arrays, const auto& ends, const auto& laws,
          std::size_t b, float* out) {
        definite_block_lanes<where(), shared()>(
            x, inverse_length, c_x, c_v, u, inverse_mass, stride, b * kSpringBlock, ends, laws,
            block_live_[b], block_packed_[b], arrays, out, product_stride);
      },
      [&](std::size_t b, bool dead_slots, Real* out) {
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
      });
}

template class SpringLanes<float>;
template class SpringLanes<double>;

}  // namespace clothlab::detail::inline CLOTHLAB_SIMD_NAMESPACE
