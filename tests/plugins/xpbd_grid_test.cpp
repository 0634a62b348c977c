// XPBD's grid fast path (plugins/integrators/xpbd_grid.hpp, xpbd_row_kernel.hpp): the
// Provot grid is recognised from the topology alone, only when every colour is one whole
// stencil parity with one spring law; and the row kernels and the wavefront give the
// general path's Gauss-Seidel: the same cloth with its colours split in halves (the same
// sweep order, which the recogniser does not take for a grid) ends in the same state,
// closer than a change of colour order moves it.
#include "xpbd_grid.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <utility>
#include <vector>

#include "integrator_harness.hpp"
#include "spring_host.hpp"

namespace clothlab::test {
namespace {

constexpr double g = 9.81;
constexpr double spacing = 0.01;

struct Stencil {
  uint32_t row_step;
  int32_t col_step;
  double ks, kd;
};
// Structural, shear, flexion, in the host's stencil order.
const Stencil stencils[] = {{0, 1, 800.0, 0.05}, {1, 0, 800.0, 0.05}, {1, 1, 60.0, 0.01},
                            {1, -1, 60.0, 0.01}, {0, 2, 5.0, 0.0},    {2, 0, 5.0, 0.0}};

// A rows x cols Provot grid coloured as the host colours it: stencil by stencil, parity 0
// then 1 ((along / step) % 2 along the stencil's direction).
struct ProvotGrid {
  std::vector<TestSpring> springs;
  std::vector<std::vector<uint32_t>> colors;

  ProvotGrid(uint32_t rows, uint32_t cols) {
    for (const Stencil& s : stencils) {
      std::vector<uint32_t> parity[2];
      const double rest = spacing * std::hypot(s.row_step, s.col_step);
      for (uint32_t r = 0; r + s.row_step < rows; ++r)
        for (uint32_t c = 0; c < cols; ++c) {
          const int64_t partner_col = int64_t{c} + s.col_step;
          if (partner_col < 0 || partner_col >= cols) continue;
          const uint32_t along = s.row_step == 0 ? c : r;
          const uint32_t step = s.row_step == 0 ? static_cast<uint32_t>(s.col_step) : s.row_step;
          parity[(along / step) % 2].push_back(static_cast<uint32_t>(springs.size()));
          springs.push_back({r * cols + c,
                             static_cast<uint32_t>((r + s.row_step) * cols + partner_col), rest,
                             s.ks, s.kd});
        }
      colors.push_back(parity[0]);
      colors.push_back(parity[1]);
    }
  }
};

// Each colour split into two independent halves, one after the other: the same sweep.
std::vector<std::vector<uint32_t>> halves(const std::vector<std::vector<uint32_t>>& colors) {
  std::vector<std::vector<uint32_t>> out;
  for (const std::vector<uint32_t>& color : colors) {
    const auto middle = color.begin() + static_cast<std::ptrdiff_t>(color.size() / 2);
    out.emplace_back(color.begin(), middle);
    out.emplace_back(middle, color.end());
  }
  return out;
}

// The positions and velocities after 10 steps, every particle started moving (pins too).
template <class Real>
std::vector<double> state_after(uint32_t rows, uint32_t cols,
                                const std::vector<std::vector<uint32_t>>& colors, int iterations,
                                const std::vector<uint32_t>& pins) {
  const ProvotGrid grid(rows, cols);
  SpringHost<Real> network(rows * cols, pins, grid.springs, {0, -g, 0});
  network.set_spring_colors(colors);
  MockSystem<Real>& system = network.system();
  for (uint32_t r = 0; r < rows; ++r)
    for (uint32_t c = 0; c < cols; ++c) {
      system.set_position(r * cols + c, {spacing * c, -spacing * r, 0});
      system.set_velocity(r * cols + c, {0, 0, 2.0 * std::sin(0.3 * (r * cols + c))});
    }
  Integrator xpbd("xpbd");
  xpbd.with("substeps", 4).with("iterations", iterations).with("threads", 1);
  xpbd.start(system);
  xpbd.run(system, 10, 1e-2);
  std::vector<double> state;
  for (uint32_t i = 0; i < rows * cols; ++i)
    for (const Vec3& q : {system.position(i), system.velocity(i)})
      state.insert(state.end(), q.begin(), q.end());
  return state;
}

// Over the positions of two states (position, velocity per particle).
double largest_position_difference(const std::vector<double>& a, const std::vector<double>& b) {
  double largest = 0;
  for (size_t k = 0; k < a.size(); ++k)
    if (k % 6 < 3) largest = std::max(largest, std::abs(a[k] - b[k]));
  return largest;
}

constexpr uint32_t rows = 23, cols = 37;
// The top corners, as the host's sheet pins them.
const std::vector<uint32_t> corner_pins = {0, cols - 1};
// Pins inside rows too (the grid path's runs of uniform inverse mass end around them), in
// the middle of in-row runs of 32 and rows of 16 and at a tail, and a whole column.
std::vector<uint32_t> scattered_pins() {
  std::vector<uint32_t> pins = {0, 5 * cols + 17, 9 * cols + 3, 14 * cols + 33, 14 * cols + 34};
  for (uint32_t r = 0; r < rows; ++r) pins.push_back(r * cols + 29);
  return pins;
}

// Grid path against general path, and against a reordered sweep as the scale of a real
// difference. 37 columns: in-row runs of 32 plus a tail, rows of 16 plus a tail.
template <class Real>
void expect_grid_path_is_the_general_sweep(int iterations, double tolerance,
                                           const std::vector<uint32_t>& pins = corner_pins) {
  const ProvotGrid grid(rows, cols);
  const std::vector<double> fast = state_after<Real>(rows, cols, grid.colors, iterations, pins);
  const std::vector<double> general =
      state_after<Real>(rows, cols, halves(grid.colors), iterations, pins);
  std::vector<std::vector<uint32_t>> reordered(grid.colors.rbegin(), grid.colors.rend());
  const std::vector<double> other_order =
      state_after<Real>(rows, cols, halves(reordered), iterations, pins);
  EXPECT_LT(largest_position_difference(fast, general), tolerance);
  EXPECT_GT(largest_position_difference(other_order, general), 10 * tolerance)
      << "the tolerance does not resolve a change of sweep order";
}

TEST(XpbdGrid, FastPathIsTheGeneralSweepFloat64) {
  expect_grid_path_is_the_general_sweep<double>(1, 1e-12);
  expect_grid_path_is_the_general_sweep<double>(3, 1e-12);  // lambda kept between iterations
}

TEST(XpbdGrid, FastPathIsTheGeneralSweepFloat32) {
  // The AVX-512 kernel's 1 / length and 1 / denominator are within ~2 ulp, not exact.
  expect_grid_path_is_the_general_sweep<float>(1, 1e-6);
  expect_grid_path_is_the_general_sweep<float>(3, 1e-6);
}

TEST(XpbdGrid, FastPathIsTheGeneralSweepWithPinsInsideRows) {
  expect_grid_path_is_the_general_sweep<double>(1, 1e-12, scattered_pins());
  expect_grid_path_is_the_general_sweep<float>(1, 1e-6, scattered_pins());
  // The middle particle pinned: no uniform inverse mass to take.
  std::vector<uint32_t> middle = scattered_pins();
  middle.push_back(rows / 2 * cols + cols / 2);
  expect_grid_path_is_the_general_sweep<float>(1, 1e-6, middle);
}

// The grid path keeps its displacements in v during a substep: the pins' velocities must
// come back bit for bit, and their positions never move.
template <class Real>
void expect_pins_keep_their_state() {
  const ProvotGrid grid(rows, cols);
  const std::vector<uint32_t> pins = scattered_pins();
  const std::vector<double> state = state_after<Real>(rows, cols, grid.colors, 1, pins);
  for (uint32_t i : pins) {
    const auto [r, c] = std::pair{i / cols, i % cols};
    const std::array<double, 6> start = {spacing * c, -spacing * r,           0, 0,
                                         0,           2.0 * std::sin(0.3 * i)};
    for (std::size_t k = 0; k < 6; ++k)
      EXPECT_EQ(state[6 * i + k], static_cast<double>(static_cast<Real>(start[k])))
          << "pin " << i << " component " << k;
  }
}

TEST(XpbdGrid, PinsKeepTheirPositionAndVelocityBitForBit) {
  expect_pins_keep_their_state<double>();
  expect_pins_keep_their_state<float>();
}

// The topology of a mock network as the recogniser sees it.
template <class Body>
void with_topology(uint32_t n, const std::vector<TestSpring>& springs,
                   const std::vector<std::vector<uint32_t>>& colors, Body&& body) {
  SpringHost<double> network(n, {}, springs, {0, 0, 0});
  network.set_spring_colors(colors);
  const auto& raw = network.system().raw();
  const auto* table = static_cast<const clothlab_topology_extension*>(
      raw.get_extension(raw.context, CLOTHLAB_EXT_TOPOLOGY));
  ASSERT_NE(table, nullptr);
  clothlab_topology topology{};
  topology.struct_size = sizeof topology;
  ASSERT_EQ(table->get(raw.context, &topology), CLOTHLAB_OK);
  body(sdk::Topology(topology));
}

TEST(XpbdGrid, RecognisesTheProvotGridAndItsColours) {
  const ProvotGrid grid(7, 9);
  with_topology(63, grid.springs, grid.colors, [](const sdk::Topology& topology) {
    const auto layout = builtin::recognise_grid(topology);
    ASSERT_TRUE(layout.has_value());
    EXPECT_EQ(layout->rows, 7u);
    EXPECT_EQ(layout->cols, 9u);
    ASSERT_EQ(layout->colors.size(), 12u);
    for (uint32_t c = 0; c < 12; ++c) {
      EXPECT_EQ(layout->colors[c].stencil, c / 2);
      EXPECT_EQ(layout->colors[c].parity, c % 2);
    }
    EXPECT_DOUBLE_EQ(layout->colors[0].ks, 800.0);
    EXPECT_DOUBLE_EQ(layout->colors[11].rest, 2 * spacing);
  });
}

TEST(XpbdGrid, RefusesWhatIsNotOneStencilParityPerColour) {
  const ProvotGrid grid(7, 9);
  // Halves of colours: each colour a part of a stencil parity.
  with_topology(63, grid.springs, halves(grid.colors), [](const sdk::Topology& topology) {
    EXPECT_FALSE(builtin::recognise_grid(topology).has_value());
  });
  // Two parities in one colour (not independent, but the recogniser must not care).
  std::vector<std::vector<uint32_t>> merged = grid.colors;
  merged[0].insert(merged[0].end(), merged[1].begin(), merged[1].end());
  merged.erase(merged.begin() + 1);
  with_topology(63, grid.springs, merged, [](const sdk::Topology& topology) {
    EXPECT_FALSE(builtin::recognise_grid(topology).has_value());
  });
  // One spring of another law in a colour.
  std::vector<TestSpring> uneven = grid.springs;
  uneven[grid.colors[2][3]].ks *= 2;
  with_topology(63, uneven, grid.colors, [](const sdk::Topology& topology) {
    EXPECT_FALSE(builtin::recognise_grid(topology).has_value());
  });
  // A chain is no grid.
  with_topology(5, {{0, 1, 0.1, 1, 0}, {1, 2, 0.1, 1, 0}, {2, 3, 0.1, 1, 0}, {3, 4, 0.1, 1, 0}},
                {{0, 2}, {1, 3}}, [](const sdk::Topology& topology) {
                  EXPECT_FALSE(builtin::recognise_grid(topology).has_value());
                });
}

}  // namespace
}  // namespace clothlab::test
