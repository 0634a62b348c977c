// XPBD's grid fast path (plugins/integrators/xpbd_grid.hpp, xpbd_grid_sweep.hpp,
// xpbd_row_kernel.hpp): taken only when the host offers clothlab.grid/1 with a stencil for
// every colour and every colour has springs; and the row kernels and the wavefront give the
// general path's Gauss-Seidel: the same cloth on a host that offers no grid ends in the same
// state, closer than a change of colour order moves it.
#include "xpbd_grid.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <limits>
#include <utility>
#include <vector>

#include "integrator_harness.hpp"
#include "spring_host.hpp"

namespace clothlab::test {
namespace {

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
// then 1 ((along / step) % 2 along the stencil's direction), with each colour's stencil as
// clothlab.grid/1 describes it.
struct ProvotGrid {
  std::vector<TestSpring> springs;
  std::vector<std::vector<uint32_t>> colors;
  std::vector<clothlab_grid_color> stencil_colors;

  ProvotGrid(uint32_t rows, uint32_t cols) {
    for (const Stencil& s : stencils) {
      const uint32_t col_begin = s.col_step < 0 ? static_cast<uint32_t>(-s.col_step) : 0;
      const uint32_t col_end = s.col_step > 0 ? cols - static_cast<uint32_t>(s.col_step) : cols;
      for (uint32_t parity = 0; parity < 2; ++parity)
        stencil_colors.push_back(
            {s.row_step, s.col_step, parity, rows - s.row_step, col_begin, col_end});
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

// The positions and velocities after 10 steps, every particle started moving (pins too).
// On a host that offers the grid (`on_grid`) or not; colours in the order given; Chebyshev
// acceleration (chebyshev_rho, chebyshev_delay) set when `chebyshev` is; `tethers` per
// particle (xpbd's option). With
// `parities_swapped`, the host's topology lists each stencil's two parities the other way
// round than its grid stencils: the general path sweeps in the topology's order, the grid path
// in the stencils', so the two end apart on every build (in one order, a build without the
// lane kernel (float_lanes.hpp) gives both paths the same bits).
struct ChebyshevSetting {
  double rho;
  long delay;
};
template <class Real>
std::vector<double> state_after(uint32_t rows, uint32_t cols, bool on_grid,
                                const std::vector<uint32_t>& color_order, int iterations,
                                const std::vector<uint32_t>& pins,
                                const ChebyshevSetting* chebyshev = nullptr,
                                bool parities_swapped = false, int tethers = 0,
                                uint32_t coincident = std::numeric_limits<uint32_t>::max()) {
  const ProvotGrid grid(rows, cols);
  SpringHost<Real> network(rows * cols, pins, grid.springs, {0, -g, 0});
  std::vector<std::vector<uint32_t>> colors;
  std::vector<clothlab_grid_color> stencil_colors;
  for (uint32_t c : color_order) {
    // Colours 2k and 2k + 1 are one stencil's parities 0 and 1.
    colors.push_back(grid.colors[parities_swapped ? c ^ 1u : c]);
    stencil_colors.push_back(grid.stencil_colors[c]);
  }
  network.set_spring_colors(colors);
  if (on_grid) network.set_grid(rows, cols, spacing, stencil_colors);
  MockSystem<Real>& system = network.system();
  for (uint32_t r = 0; r < rows; ++r)
    for (uint32_t c = 0; c < cols; ++c) {
      system.set_position(r * cols + c, {spacing * c, -spacing * r, 0});
      system.set_velocity(r * cols + c, {0, 0, 2.0 * std::sin(0.3 * (r * cols + c))});
    }
  // Particle `coincident` moved onto its right-hand neighbour, with its velocity.
  if (coincident < rows * cols) {
    system.set_position(coincident, system.position(coincident + 1));
    system.set_velocity(coincident, system.velocity(coincident + 1));
  }
  Integrator xpbd("xpbd");
  xpbd.with("inner_substeps", 4)
      .with("iterations", iterations)
      .with("threads", 1)
      .with("tethers", tethers);
  if (chebyshev != nullptr)
    xpbd.with("chebyshev_rho", chebyshev->rho)
        .with("chebyshev_delay", static_cast<double>(chebyshev->delay));
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
// the middle of in-row runs (32 particles at 16 lanes, 16 at 8) and of row blocks (16 and 8
// springs) and at a tail, and a whole column.
std::vector<uint32_t> scattered_pins() {
  std::vector<uint32_t> pins = {0, 5 * cols + 17, 9 * cols + 3, 14 * cols + 33, 14 * cols + 34};
  for (uint32_t r = 0; r < rows; ++r) pins.push_back(r * cols + 29);
  return pins;
}

// Grid path against general path, and against a reordered sweep as the scale of a real
// difference. 37 columns: whole in-row runs and row blocks plus a tail at 16 lanes and at 8.
template <class Real>
void expect_grid_path_is_the_general_sweep(int iterations, double tolerance,
                                           const std::vector<uint32_t>& pins = corner_pins,
                                           int tethers = 0) {
  std::vector<uint32_t> order(12), reversed(12);
  for (uint32_t c = 0; c < 12; ++c) order[c] = c, reversed[c] = 11 - c;
  const auto state = [&](bool on_grid, const std::vector<uint32_t>& colors) {
    return state_after<Real>(rows, cols, on_grid, colors, iterations, pins, nullptr, false,
                             tethers);
  };
  const std::vector<double> fast = state(true, order);
  const std::vector<double> general = state(false, order);
  const std::vector<double> other_order = state(false, reversed);
  EXPECT_LT(largest_position_difference(fast, general), tolerance);
  EXPECT_GT(largest_position_difference(other_order, general), 10 * tolerance)
      << "the tolerance does not resolve a change of sweep order";
}

TEST(XpbdGrid, FastPathIsTheGeneralSweepFloat64) {
  expect_grid_path_is_the_general_sweep<double>(1, 1e-12);
  expect_grid_path_is_the_general_sweep<double>(3, 1e-12);  // lambda kept between iterations
}

TEST(XpbdGrid, FastPathIsTheGeneralSweepFloat32) {
  // The lane kernel's 1 / length and 1 / denominator are within a few ulp, not exact.
  expect_grid_path_is_the_general_sweep<float>(1, 1e-6);
  expect_grid_path_is_the_general_sweep<float>(3, 1e-6);
}

// Two particles on one spot, moving together, start a structural spring of the first colour:
// at its projection it has no direction, and the lane kernels push its ends by nothing (their
// inverse length is not finite there, so only the kernels' masks keep it out: the uniform
// push, the pushes of runs with pins, the multipliers kept between iterations, on the grid
// path and the general one). The float32 lanes end where the float64 path does, to its rounding.
TEST(XpbdGrid, CoincidentEndsArePushedByNothing) {
  std::vector<uint32_t> order(12);
  for (uint32_t c = 0; c < 12; ++c) order[c] = c;
  const uint32_t coincident = 5 * cols + 10;  // column 10: the (0, 1) stencil's parity 0
  // A pin in the coincident spring's row: its run of springs is not of the uniform weight.
  const std::vector<uint32_t> pinned_row = {0, cols - 1, 5 * cols + 14};
  for (const bool on_grid : {true, false})
    for (const int iterations : {1, 3})
      for (const std::vector<uint32_t>* pins : {&corner_pins, &pinned_row}) {
        const auto state = [&](auto real) {
          return state_after<decltype(real)>(rows, cols, on_grid, order, iterations, *pins, nullptr,
                                             false, 0, coincident);
        };
        const std::vector<double> lanes = state(float{}), reference = state(double{});
        SCOPED_TRACE(testing::Message() << "on_grid " << on_grid << ", iterations " << iterations
                                        << ", pins " << pins->size());
        for (double value : lanes) ASSERT_TRUE(std::isfinite(value));
        EXPECT_LT(largest_position_difference(lanes, reference), 1e-5);
      }
}

TEST(XpbdGrid, FastPathIsTheGeneralSweepWithPinsInsideRows) {
  expect_grid_path_is_the_general_sweep<double>(1, 1e-12, scattered_pins());
  expect_grid_path_is_the_general_sweep<float>(1, 1e-6, scattered_pins());
  // The middle particle pinned: no uniform inverse mass to take.
  std::vector<uint32_t> middle = scattered_pins();
  middle.push_back(rows / 2 * cols + cols / 2);
  expect_grid_path_is_the_general_sweep<float>(1, 1e-6, middle);
}

// The tethers, projected row by row in the grid sweep's wavefront (and by each SIMD target's
// copy of it) and after the whole sweep on the general path.
TEST(XpbdGrid, FastPathIsTheGeneralSweepWithTethers) {
  expect_grid_path_is_the_general_sweep<double>(1, 1e-12, corner_pins, 3);
  expect_grid_path_is_the_general_sweep<float>(1, 1e-6, corner_pins, 3);
  expect_grid_path_is_the_general_sweep<float>(1, 1e-6, scattered_pins(), 3);
}

// The grid sweep's velocity pass reports a speed that is not finite: one particle of the last
// row starts at infinite speed, far from the pinned top row (whose pass takes the weights), so
// only the pin-free runs' pass sees the speeds that came out NaN or infinite in one substep.
template <class Real>
clothlab_status step_with_an_infinite_speed() {
  const ProvotGrid grid(rows, cols);
  SpringHost<Real> network(rows * cols, corner_pins, grid.springs, {0, -g, 0});
  network.set_spring_colors(grid.colors);
  network.set_grid(rows, cols, spacing, grid.stencil_colors);
  MockSystem<Real>& system = network.system();
  for (uint32_t r = 0; r < rows; ++r)
    for (uint32_t c = 0; c < cols; ++c)
      system.set_position(r * cols + c, {spacing * c, -spacing * r, 0});
  system.set_velocity((rows - 1) * cols + 20, {0, 0, std::numeric_limits<double>::infinity()});
  Integrator xpbd("xpbd");
  xpbd.with("threads", 1);
  xpbd.start(system);
  return xpbd.step(system, 0.0, 1e-3);
}

TEST(XpbdGrid, ReportsANonFiniteSpeedAsNumerical) {
  EXPECT_EQ(step_with_an_infinite_speed<float>(), CLOTHLAB_ERROR_NUMERICAL);
  EXPECT_EQ(step_with_an_infinite_speed<double>(), CLOTHLAB_ERROR_NUMERICAL);
}

// A grid cloth on the host whose topology swaps the parities (state_after): the grid path and
// the general path end apart, and a setting's bits say which path it took.
template <class Real>
std::vector<double> swapped_parities_state(bool on_grid, const ChebyshevSetting* chebyshev) {
  std::vector<uint32_t> order(12);
  for (uint32_t c = 0; c < 12; ++c) order[c] = c;
  return state_after<Real>(rows, cols, on_grid, order, 3, corner_pins, chebyshev, true);
}

// Chebyshev acceleration on (chebyshev_delay below the iterations): a grid cloth takes the
// general sweep, the same bits as on a host without a grid; off (rho 0, any delay): the grid
// path's bits.
TEST(XpbdGrid, ChebyshevTakesTheGeneralPathAndOffKeepsTheGridPath) {
  const ChebyshevSetting accelerating{0.5, 1}, off{0.0, 1};
  const std::vector<double> grid = swapped_parities_state<float>(true, nullptr);
  const std::vector<double> general = swapped_parities_state<float>(false, nullptr);
  ASSERT_NE(grid, general) << "the two paths cannot be told apart";
  const std::vector<double> accelerated = swapped_parities_state<float>(true, &accelerating);
  const std::vector<double> accelerated_general =
      swapped_parities_state<float>(false, &accelerating);
  ASSERT_NE(accelerated, grid) << "the accelerated sweeps cannot be told from the grid path";
  EXPECT_EQ(accelerated, accelerated_general);
  EXPECT_EQ(swapped_parities_state<float>(true, &off), grid);
}

// A delay of the iterations or more leaves every weight 1: nothing to accelerate, so the grid
// cloth keeps the grid path (not the general one, which would give the same sweeps slower and
// check them for divergence).
TEST(XpbdGrid, ChebyshevDelayedPastTheIterationsKeepsTheGridPath) {
  const std::vector<double> grid = swapped_parities_state<double>(true, nullptr);
  ASSERT_NE(grid, swapped_parities_state<double>(false, nullptr))
      << "the two paths cannot be told apart";
  for (const ChebyshevSetting delayed : {ChebyshevSetting{0.9, 3}, ChebyshevSetting{0.9, 10}})
    EXPECT_EQ(swapped_parities_state<double>(true, &delayed), grid) << "delay " << delayed.delay;
}

// The grid path keeps its displacements in v during a substep: the pins' velocities must
// come back bit for bit, and their positions never move.
template <class Real>
void expect_pins_keep_their_state() {
  const std::vector<uint32_t> pins = scattered_pins();
  std::vector<uint32_t> order(12);
  for (uint32_t c = 0; c < 12; ++c) order[c] = c;
  const std::vector<double> state = state_after<Real>(rows, cols, true, order, 1, pins);
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

// The grid layout XPBD takes from a mock network's topology and grid.
template <class Body>
void with_layout(const ProvotGrid& grid, const std::vector<std::vector<uint32_t>>& colors,
                 const std::vector<clothlab_grid_color>* stencil_colors, Body&& body) {
  SpringHost<double> network(63, {}, grid.springs, {0, 0, 0});
  network.set_spring_colors(colors);
  if (stencil_colors != nullptr) network.set_grid(7, 9, spacing, *stencil_colors);
  const sdk::System<double> system(network.system().raw());
  body(builtin::grid_layout(system.grid(), system.topology()));
}

TEST(XpbdGrid, LaysTheTopologysColoursOnTheHostsGrid) {
  const ProvotGrid grid(7, 9);
  with_layout(grid, grid.colors, &grid.stencil_colors, [](const auto& layout) {
    ASSERT_TRUE(layout.has_value());
    EXPECT_EQ(layout->rows, 7u);
    EXPECT_EQ(layout->cols, 9u);
    ASSERT_EQ(layout->colors.size(), 12u);
    for (uint32_t c = 0; c < 12; ++c) {
      EXPECT_EQ(layout->colors[c].row_step, stencils[c / 2].row_step);
      EXPECT_EQ(layout->colors[c].col_step, stencils[c / 2].col_step);
      EXPECT_EQ(layout->colors[c].parity, c % 2);
    }
    EXPECT_DOUBLE_EQ(layout->colors[0].ks, 800.0);
    EXPECT_DOUBLE_EQ(layout->colors[11].rest, 2 * spacing);
  });
}

TEST(XpbdGrid, TakesTheGeneralPathWithoutAGridStencilsOrSprings) {
  const ProvotGrid grid(7, 9);
  // No grid offered: a general mesh, however its springs lie.
  with_layout(grid, grid.colors, nullptr,
              [](const auto& layout) { EXPECT_FALSE(layout.has_value()); });
  // A grid whose colours are no stencils (the reference system's first-fit colours).
  const std::vector<clothlab_grid_color> none;
  with_layout(grid, grid.colors, &none,
              [](const auto& layout) { EXPECT_FALSE(layout.has_value()); });
  // A colour without springs (its family has ks = kd = 0): no law to project it with.
  std::vector<std::vector<uint32_t>> emptied = grid.colors;
  emptied[5].clear();
  with_layout(grid, emptied, &grid.stencil_colors,
              [](const auto& layout) { EXPECT_FALSE(layout.has_value()); });
}

}  // namespace
}  // namespace clothlab::test
