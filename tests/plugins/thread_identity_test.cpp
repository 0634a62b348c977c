// Every built-in that runs its own parallel loops (vbd, xpbd) gives the same bits on any thread
// count: its `threads` parameter at 1, 2 and 3, and at 0 on a host that offers 2 or 3
// (clothlab.threads/1, the count sdk/threads.hpp resolves). One network serves them all: a
// rows x cols grid of unit masses with structural springs, offered with the particle colours
// vbd sweeps (a checkerboard), the spring colours xpbd sweeps (direction x parity) and the grid
// (xpbd's grid path), the two top corners pinned, under gravity, started with a sideways kick
// so every spring works. xpbd's grid sweep computes a position-dependent external field
// itself, a few rows ahead, through clothlab.external-forces/2: the bits of /1's call before
// each substep, on any thread count.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <ostream>
#include <string>
#include <utility>
#include <vector>

#include "integrator_harness.hpp"
#include "spring_host.hpp"

namespace clothlab::test {
namespace {

struct ThreadedCase {
  const char* name;
  const char* integrator;
  bool float32;
  uint32_t side;  // above the plugin's threshold for running in parallel
  int steps;
  std::vector<std::pair<const char*, double>> params;
};

void PrintTo(const ThreadedCase& c, std::ostream* out) { *out << c.name; }

// The threads the plugin is asked for: its parameter, or 0 and the host's offer.
struct ThreadChoice {
  int parameter;
  uint32_t host;  // 0: the host offers no count
};

// The spring host's external field (SpringHost::set_position_field): its strength (0: gravity
// alone) and whether the host offers it through clothlab.external-forces/2's rows call.
struct ExternalField {
  double strength = 0;
  bool rows_call = true;
};

template <class Real>
std::vector<double> grid_state_after(const ThreadedCase& c, ThreadChoice threads,
                                     ExternalField field = {}) {
  const uint32_t rows = c.side, cols = c.side, n = rows * cols;
  std::vector<TestSpring> springs;
  std::vector<std::vector<uint32_t>> spring_colors(4), particle_colors(2);
  const auto add = [&](uint32_t i, uint32_t j, uint32_t color) {
    spring_colors[color].push_back(static_cast<uint32_t>(springs.size()));
    springs.push_back({i, j, 0.01, 500.0, 0.1});
  };
  for (uint32_t r = 0; r < rows; ++r)
    for (uint32_t col = 0; col < cols; ++col) {
      if (col + 1 < cols) add(r * cols + col, r * cols + col + 1, col % 2);
      if (r + 1 < rows) add(r * cols + col, (r + 1) * cols + col, 2 + r % 2);
      particle_colors[(r + col) % 2].push_back(r * cols + col);
    }
  SpringHost<Real> network(n, {0, cols - 1}, std::move(springs), {0, -9.81, 0});
  network.set_spring_colors(spring_colors);
  network.set_particle_colors(particle_colors);
  network.set_grid(rows, cols, 0.01,
                   {{0, 1, 0, rows, 0, cols - 1},
                    {0, 1, 1, rows, 0, cols - 1},
                    {1, 0, 0, rows - 1, 0, cols},
                    {1, 0, 1, rows - 1, 0, cols}});
  network.set_threads(threads.host);
  network.set_position_field(field.strength, field.rows_call);
  MockSystem<Real>& system = network.system();
  for (uint32_t i = 0; i < n; ++i) {
    system.set_position(i, {0.01 * (i % cols), -0.01 * (i / cols), 0});
    system.set_velocity(i, {0, 0, std::sin(0.1 * i)});
  }
  Integrator integrator(c.integrator);
  integrator.with("threads", threads.parameter);
  for (const auto& [name, value] : c.params) integrator.with(name, value);
  integrator.start(system);
  integrator.run(system, c.steps, 5e-3);
  std::vector<double> state;
  for (uint32_t i = 0; i < n; ++i)
    for (const Vec3& q : {system.position(i), system.velocity(i)})
      state.insert(state.end(), q.begin(), q.end());
  return state;
}

std::vector<double> state_after(const ThreadedCase& c, ThreadChoice threads,
                                ExternalField field = {}) {
  return c.float32 ? grid_state_after<float>(c, threads, field)
                   : grid_state_after<double>(c, threads, field);
}

// Values of two states that differ in their bits.
size_t differing_values(const std::vector<double>& a, const std::vector<double>& b) {
  size_t differing = 0;
  for (size_t k = 0; k < a.size(); ++k) differing += std::memcmp(&a[k], &b[k], 8) != 0;
  return differing;
}

// The field's rows computed inside the sweep, ahead of its predict pass, on one thread, two
// bands and a band of two threads: /1's call before each substep, bit for bit. The host offers
// 3 threads, a scratch slot for each sweep thread.
TEST(XpbdExternalRows, AheadOfThePredictAreTheBitsOfTheWholeCall) {
  for (const bool float32 : {true, false}) {
    const ThreadedCase c{"", "xpbd", float32, 190, 3, {{"inner_substeps", 3}, {"iterations", 2}}};
    const ExternalField field{400.0, true}, whole{400.0, false};
    const std::vector<double> expected = state_after(c, {1, 3}, whole);
    ASSERT_GT(differing_values(expected, state_after(c, {1, 3})), 0u) << "the field does nothing";
    for (const int threads : {1, 2, 3})
      EXPECT_EQ(differing_values(state_after(c, {threads, 3}, field), expected), 0u)
          << threads << " threads, float32 " << float32;
  }
}

class BitwiseIdenticalAcrossThreadCounts : public ::testing::TestWithParam<ThreadedCase> {};

TEST_P(BitwiseIdenticalAcrossThreadCounts, OnAGrid) {
  const ThreadedCase& c = GetParam();
  const std::vector<double> one = state_after(c, {1, 0});
  for (const ThreadChoice threads :
       {ThreadChoice{2, 0}, ThreadChoice{3, 0}, ThreadChoice{0, 2}, ThreadChoice{0, 3}}) {
    const std::vector<double> many = state_after(c, threads);
    ASSERT_EQ(many.size(), one.size());
    size_t differing = 0;
    for (size_t k = 0; k < one.size(); ++k) differing += std::memcmp(&one[k], &many[k], 8) != 0;
    EXPECT_EQ(differing, 0u) << "threads parameter " << threads.parameter << ", host's count "
                             << threads.host;
  }
}

// vbd runs in parallel from 4096 free particles, xpbd from 65 536 springs.
INSTANTIATE_TEST_SUITE_P(
    BuiltinsThatThread, BitwiseIdenticalAcrossThreadCounts,
    ::testing::Values(
        ThreadedCase{"VbdFloat64", "vbd", false, 70, 3, {{"iterations", 3}}},
        ThreadedCase{"VbdFloat32", "vbd", true, 70, 3, {{"iterations", 3}}},
        ThreadedCase{
            "XpbdFloat64", "xpbd", false, 190, 4, {{"inner_substeps", 4}, {"iterations", 2}}},
        ThreadedCase{
            "XpbdFloat32", "xpbd", true, 190, 4, {{"inner_substeps", 4}, {"iterations", 2}}},
        ThreadedCase{"XpbdChebyshev",
                     "xpbd",
                     false,
                     190,
                     4,
                     {{"inner_substeps", 4},
                      {"iterations", 4},
                      {"chebyshev_rho", 0.5},
                      {"chebyshev_delay", 1}}},
        // float32 on the general path: its colours' lane blocks (xpbd_color_blocks.hpp).
        ThreadedCase{"XpbdChebyshevFloat32",
                     "xpbd",
                     true,
                     190,
                     2,
                     {{"inner_substeps", 2},
                      {"iterations", 2},
                      {"chebyshev_rho", 0.5},
                      {"chebyshev_delay", 1}}},
        ThreadedCase{"XpbdWithTethers",
                     "xpbd",
                     true,
                     190,
                     4,
                     {{"inner_substeps", 4}, {"iterations", 2}, {"tethers", 2}}}),
    [](const ::testing::TestParamInfo<ThreadedCase>& info) {
      return std::string(info.param.name);
    });

}  // namespace
}  // namespace clothlab::test
