// XPBD's general sweep on lanes (plugins/integrators/xpbd_color_blocks.hpp), on the SIMD target
// that runs here (make_lane_blocks: each target of a portable build in turn): the blocks that
// load their ends in order or as split runs give the bits of the same springs gathered, with
// their windows loaded and stored whole or under masks; a window loaded whole holds no
// particle that another thread's blocks join; and the lanes give the one-spring law
// (xpbd_constraint.hpp) to within the lane kernel's rounding. The net holds every kind of
// block (checked on the build's own lanes).
#include "xpbd_color_blocks.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>
#include <vector>

#include "xpbd_general_sweep.hpp"

namespace clothlab::test {
namespace {

using builtin::Constraint;

constexpr uint32_t rows = 23, cols = 37;
constexpr float spacing = 0.01f;
constexpr std::size_t stride = std::size_t{rows} * cols + 5;  // padded, as a system's

// Coloured springs of a rows x cols net, each colour a kind of block: the springs of one
// stencil whose first particles have one parity along it (every other row: runs in order;
// every other column: split pairs; columns 0, 1 of every 4 two apart: split quads) and
// diagonals from every other column (every other particle, offset cols + 1). Row ends leave
// runs with holes and springs no run takes (gathered). Particle 40 is pinned. The vertical
// springs' rest lengths differ along a row (a law per lane), the others' are the colour's.
struct ColoredNet {
  std::vector<Constraint<float>> springs;
  std::vector<uint32_t> color_offsets{0};
  std::vector<float> inverse_mass;  // the springs' weights by particle

  ColoredNet() {
    const auto weight = [](uint32_t i) {
      return i == 40 ? 0.0f : 900.0f + static_cast<float>(i % 7);
    };
    for (uint32_t i = 0; i < rows * cols; ++i) inverse_mass.push_back(weight(i));
    const auto add = [&](uint32_t i, uint32_t j, float rest, float ks, float kd) {
      springs.push_back({i, j, rest, ks, kd, weight(i), weight(j)});
    };
    for (uint32_t parity = 0; parity < 2; ++parity) {
      for (uint32_t r = parity; r + 1 < rows; r += 2)
        for (uint32_t c = 0; c < cols; ++c)
          add(r * cols + c, (r + 1) * cols + c, spacing * (1 + 0.02f * (c % 3)), 800, 0.05f);
      color_offsets.push_back(static_cast<uint32_t>(springs.size()));
      for (uint32_t r = 0; r < rows; ++r)
        for (uint32_t c = parity; c + 1 < cols; c += 2)
          add(r * cols + c, r * cols + c + 1, spacing, 800, 0.05f);
      color_offsets.push_back(static_cast<uint32_t>(springs.size()));
      for (uint32_t r = 0; r < rows; ++r)
        for (uint32_t c = 0; c + 2 < cols; ++c)
          if ((c / 2) % 2 == parity) add(r * cols + c, r * cols + c + 2, 2 * spacing, 5, 0);
      color_offsets.push_back(static_cast<uint32_t>(springs.size()));
      for (uint32_t r = parity; r + 1 < rows; r += 2)
        for (uint32_t c = 0; c + 1 < cols; c += 2)
          if (r > 1 || c != 10)  // a hole in the first run
            add(r * cols + c, (r + 1) * cols + c + 1, spacing * std::sqrt(2.0f), 60, 0.01f);
      color_offsets.push_back(static_cast<uint32_t>(springs.size()));
    }
  }
};

struct Sweep {
  std::vector<float> displacement, lambda;
};

// The lane blocks of the target that runs here, built for `threads`; none without lanes.
std::unique_ptr<builtin::LaneBlocks> lane_blocks(const ColoredNet& net, int threads,
                                                 bool find_runs = true) {
  std::unique_ptr<builtin::LaneBlocks> blocks = builtin::make_lane_blocks();
  if (blocks != nullptr)
    blocks->build(net.springs, net.color_offsets, rows * cols, threads, find_runs);
  return blocks;
}

// Two Gauss-Seidel iterations (the second reads the multipliers) from a perturbed net, on one
// thread; `whole` false: every run with dead lanes loads and stores under masks.
Sweep sweep_blocks(const ColoredNet& net, bool find_runs, bool whole = true) {
  const std::unique_ptr<builtin::LaneBlocks> blocks = lane_blocks(net, 1, find_runs);
  std::vector<float> x(3 * stride, 0.0f), dx(3 * stride, 0.0f), lambda(blocks->slots(), 0.0f);
  for (uint32_t i = 0; i < rows * cols; ++i) {
    x[i] = spacing * static_cast<float>(i % cols);
    x[stride + i] = -spacing * static_cast<float>(i / cols);
    x[2 * stride + i] = 0.002f * std::sin(0.7f * static_cast<float>(i));
    for (std::size_t k = 0; k < 3; ++k)
      dx[k * stride + i] = i == 40 ? 0.0f : 1e-3f * std::cos(1.3f * static_cast<float>(i + 5 * k));
  }
  const float h = 1e-2f;
  for (int iteration = 0; iteration < 2; ++iteration) {
    const builtin::LaneArrays arrays{
        x.data(),      dx.data(),      net.inverse_mass.data(),
        lambda.data(), stride,         h,
        h * h,         iteration == 0, true,
        whole ? 1 : 0};  // 0: not the thread count built for, so every window masked
    for (std::size_t c = 0; c + 1 < net.color_offsets.size(); ++c)
      blocks->project(blocks->blocks_begin(c), blocks->blocks_begin(c + 1), arrays);
  }
  return {dx, lambda};
}

TEST(XpbdColorBlocks, TheNetHoldsEveryKindOfBlock) {
#if defined(CLOTHLAB_FLOAT_LANES)
  const ColoredNet net;
  builtin::ColorBlocks blocks;
  blocks.build(net.springs, net.color_offsets, rows * cols, 1);
  using Kind = builtin::ColorBlocks::Kind;
  for (Kind kind :
       {Kind::kInOrder, Kind::kSplitPairs, Kind::kSplitQuads, Kind::kEveryOther, Kind::kGathered})
    EXPECT_GT(blocks.blocks_of(kind), 0u) << "no block of kind " << static_cast<int>(kind);
  EXPECT_GT(blocks.runs_with_holes(), 0u);
#else
  GTEST_SKIP() << "a build without float lanes sweeps one spring at a time";
#endif
}

TEST(XpbdColorBlocks, RunsGiveTheBitsOfTheSameSpringsGathered) {
  const ColoredNet net;
  const std::unique_ptr<builtin::LaneBlocks> blocks = lane_blocks(net, 1);
  if (blocks == nullptr) GTEST_SKIP() << "no float lanes here: one spring at a time";
  std::size_t whole = 0;
  for (long b = 0; b < blocks->blocks_begin(net.color_offsets.size() - 1); ++b)
    whole += blocks->whole_windows(static_cast<std::size_t>(b));
  EXPECT_GT(whole, 0u);
  const Sweep runs = sweep_blocks(net, true), gathered = sweep_blocks(net, false);
  EXPECT_EQ(runs.displacement, gathered.displacement);
  EXPECT_EQ(runs.displacement, sweep_blocks(net, true, false).displacement);
}

TEST(XpbdColorBlocks, AWindowLoadedWholeHoldsNoParticleOfAnotherThreadsBlocks) {
  const ColoredNet net;
  if (builtin::make_lane_blocks() == nullptr)
    GTEST_SKIP() << "no float lanes here: one spring at a time";
  for (int threads : {2, 3}) {
    const std::unique_ptr<builtin::LaneBlocks> built = lane_blocks(net, threads);
    const builtin::LaneBlocks& blocks = *built;
    std::size_t whole = 0, kept_masked = 0;
    for (std::size_t c = 0; c + 1 < net.color_offsets.size(); ++c) {
      const long begin = blocks.blocks_begin(c), end = blocks.blocks_begin(c + 1);
      std::vector<int> share_of_particle(rows * cols, -1);  // the share whose blocks join it
      std::vector<int> stored_whole_by(rows * cols, -1);    // the share that stores it whole
      for (int t = 0; t < threads; ++t) {
        const auto [first, last] = builtin::thread_share(begin, end, t, threads);
        for (long b = first; b < last; ++b)
          for (uint32_t particle : blocks.live_particles(static_cast<std::size_t>(b)))
            share_of_particle[particle] = t;
      }
      for (int t = 0; t < threads; ++t) {
        const auto [first, last] = builtin::thread_share(begin, end, t, threads);
        for (long b = first; b < last; ++b) {
          const auto block = static_cast<std::size_t>(b);
          if (blocks.windows(block).empty()) continue;  // gathered
          bool private_windows = true;
          for (const auto& [start, width] : blocks.windows(block))
            for (uint32_t particle = start; particle < start + width; ++particle)
              private_windows =
                  private_windows && particle < rows * cols &&
                  (share_of_particle[particle] == -1 || share_of_particle[particle] == t);
          if (blocks.whole_windows(block)) {
            ++whole;
            EXPECT_TRUE(private_windows)
                << "block " << b << " of colour " << c << ", " << threads << " threads";
            for (const auto& [start, width] : blocks.windows(block))
              for (uint32_t particle = start; particle < start + width && particle < rows * cols;
                   ++particle) {
                EXPECT_TRUE(stored_whole_by[particle] == -1 || stored_whole_by[particle] == t)
                    << "particle " << particle << " stored whole by two threads, colour " << c;
                stored_whole_by[particle] = t;
              }
          } else if (!private_windows) {
            ++kept_masked;
          }
        }
      }
    }
    EXPECT_GT(whole, 0u) << threads << " threads";
    EXPECT_GT(kept_masked, 0u) << threads << " threads";  // the net has windows to keep masked
  }
}

TEST(XpbdColorBlocks, LanesGiveTheOneSpringLaw) {
  const ColoredNet net;
  if (builtin::make_lane_blocks() == nullptr)
    GTEST_SKIP() << "no float lanes here: one spring at a time";
  const Sweep lanes = sweep_blocks(net, true);
  // The same sweep one spring at a time, in double.
  std::vector<double> x(3 * stride, 0.0), dx(3 * stride, 0.0), lambda(net.springs.size(), 0.0);
  for (uint32_t i = 0; i < rows * cols; ++i) {
    x[i] = static_cast<double>(spacing * static_cast<float>(i % cols));
    x[stride + i] = static_cast<double>(-spacing * static_cast<float>(i / cols));
    x[2 * stride + i] = static_cast<double>(0.002f * std::sin(0.7f * static_cast<float>(i)));
    for (std::size_t k = 0; k < 3; ++k)
      dx[k * stride + i] =
          i == 40 ? 0.0
                  : static_cast<double>(1e-3f * std::cos(1.3f * static_cast<float>(i + 5 * k)));
  }
  const std::vector<double> start = dx;
  const double h = static_cast<double>(1e-2f);
  for (int iteration = 0; iteration < 2; ++iteration)
    for (std::size_t k = 0; k < net.springs.size(); ++k) {
      const Constraint<float>& s = net.springs[k];
      const Constraint<double> spring{s.first, s.second,       s.rest,         s.ks,
                                      s.kd,    s.first_weight, s.second_weight};
      builtin::project_constraint(spring, lambda[k], iteration == 0, x.data(), dx.data(), stride, h,
                                  static_cast<double>(static_cast<float>(h * h)));
    }
  double largest = 0, moved = 0;
  for (std::size_t e = 0; e < dx.size(); ++e) {
    largest = std::max(largest, std::abs(static_cast<double>(lanes.displacement[e]) - dx[e]));
    moved = std::max(moved, std::abs(dx[e] - start[e]));
  }
  EXPECT_GT(moved, 1e-4);  // the projections moved the particles
  EXPECT_LT(largest, 2e-8);
}

}  // namespace
}  // namespace clothlab::test
