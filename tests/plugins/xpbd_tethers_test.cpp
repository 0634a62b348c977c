// XPBD's long-range attachments (plugins/integrators/xpbd_tethers.hpp): unilateral (a particle
// inside its range moves as if there were none), a hanging cloth stays within (1 + slack) x the
// rest distance of every anchor on both the grid path and the general path, the anchors of a
// pinned edge reach above and below, and bad values are one-line errors.
#include "xpbd_tethers.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "integrator_harness.hpp"
#include "spring_host.hpp"
#include "xpbd_grid.hpp"

namespace clothlab::test {
namespace {

double distance(const Vec3& a, const Vec3& b) {
  return std::hypot(a[0] - b[0], a[1] - b[1], a[2] - b[2]);
}

// A pin at the origin and one free unit mass 1 m away along x, joined by a spring that exerts
// no force (the topology needs one), no gravity: only the tether acts.
struct PinAndParticle {
  PinAndParticle() : network(2, {0}, {{0, 1, 1.0, 0.0, 0.0}}, {0, 0, 0}) {
    network.system().set_position(1, {1, 0, 0});
  }
  SpringHost<double> network;
};

std::vector<Vec3> free_flight(Vec3 velocity, int tethers, double slack) {
  PinAndParticle scene;
  MockSystem<double>& system = scene.network.system();
  system.set_velocity(1, velocity);
  Integrator xpbd("xpbd");
  xpbd.with("inner_substeps", 4).with("tethers", tethers).with("tether_slack", slack);
  xpbd.start(system);
  std::vector<Vec3> path;
  for (int n = 0; n < 50; ++n) {
    EXPECT_EQ(xpbd.step(system, n * 0.01, 0.01), CLOTHLAB_OK) << xpbd.message();
    path.push_back(system.position(1));
  }
  return path;
}

TEST(XpbdTethers, NeverPullAParticleInsideItsRange) {
  // Moving towards the pin and across it (to 0.5 m beyond it): never farther than 1 m, so
  // the tether must not act at all, bit for bit.
  const Vec3 inwards{-3, 0.2, 0};
  const std::vector<Vec3> tethered = free_flight(inwards, 1, 0.0);
  const std::vector<Vec3> free = free_flight(inwards, 0, 0.0);
  ASSERT_LT(distance(tethered.back(), {0, 0, 0}), 1.0);
  for (size_t n = 0; n < free.size(); ++n) EXPECT_EQ(tethered[n], free[n]) << "step " << n;
}

TEST(XpbdTethers, HoldAParticleMovingAwayAtTheSlackLength) {
  const std::vector<Vec3> path = free_flight({1, 1, 0}, 1, 0.1);
  const std::vector<Vec3> free = free_flight({1, 1, 0}, 0, 0.1);
  ASSERT_GT(distance(free.back(), {0, 0, 0}), 1.4);  // untethered it flies off
  for (const Vec3& p : path) EXPECT_LE(distance(p, {0, 0, 0}), 1.1 * (1 + 1e-12));
  EXPECT_NEAR(distance(path.back(), {0, 0, 0}), 1.1, 1e-12);  // taut: on the sphere
}

// The tethers the plugin builds for `system` at its current positions.
template <class Real>
builtin::Tethers<Real> tethers_of(MockSystem<Real>& system, uint32_t per_particle, double slack) {
  const sdk::System<Real> view(system.raw());
  builtin::Tethers<Real> tethers;
  tethers.build(view.topology(), view.x(), view.stride(), view.inverse_mass(), per_particle, slack);
  return tethers;
}

// The worst distance over limit of any tether of `tethers` at the system's state.
template <class Real>
double worst_tether_ratio(const builtin::Tethers<Real>& tethers, const MockSystem<Real>& system,
                          uint32_t n) {
  double worst = 0;
  for (uint32_t i = 0; i < n; ++i)
    for (uint32_t slot = 0; slot < tethers.slots(); ++slot)
      if (std::isfinite(tethers.limit(slot, i)))
        worst =
            std::max(worst, distance(system.position(i), system.position(tethers.anchor(slot, i))) /
                                tethers.limit(slot, i));
  return worst;
}

// A soft rows x cols structural grid (4 colours, direction x parity) hung from its top row's
// two corners under gravity, offered as a grid (the grid path) or not (the general path):
// untethered its bottom corners sag far beyond 10 %.
struct SoftSheet {
  static constexpr uint32_t rows = 12, cols = 12;
  static constexpr double spacing = 0.05;
  SoftSheet(bool general) : network(rows * cols, {0, cols - 1}, springs(), {0, -g, 0}) {
    std::vector<std::vector<uint32_t>> colors(4);
    uint32_t k = 0;
    for (uint32_t r = 0; r < rows; ++r)
      for (uint32_t c = 0; c < cols; ++c) {
        if (c + 1 < cols) colors[c % 2].push_back(k++);
        if (r + 1 < rows) colors[2 + r % 2].push_back(k++);
      }
    network.set_spring_colors(colors);
    if (!general)
      network.set_grid(rows, cols, spacing,
                       {{0, 1, 0, rows, 0, cols - 1},
                        {0, 1, 1, rows, 0, cols - 1},
                        {1, 0, 0, rows - 1, 0, cols},
                        {1, 0, 1, rows - 1, 0, cols}});
    for (uint32_t r = 0; r < rows; ++r)
      for (uint32_t c = 0; c < cols; ++c)
        network.system().set_position(r * cols + c, {spacing * c, -spacing * r, 0});
  }
  static std::vector<TestSpring> springs() {
    std::vector<TestSpring> out;
    for (uint32_t r = 0; r < rows; ++r)
      for (uint32_t c = 0; c < cols; ++c) {
        if (c + 1 < cols) out.push_back({r * cols + c, r * cols + c + 1, spacing, 20.0, 0.2});
        if (r + 1 < rows) out.push_back({r * cols + c, (r + 1) * cols + c, spacing, 20.0, 0.2});
      }
    return out;
  }
  bool on_the_grid_path() {
    const sdk::System<double> view(network.system().raw());
    return builtin::grid_layout(view.grid(), view.topology()).has_value();
  }
  SpringHost<double> network;
};

// The largest distance / limit over the run, checked after every step, of the tethers with up
// to `per_particle` anchors and slack 0.1, run with `tethers` of them (0: none).
double hang(bool general, uint32_t per_particle, int tethers) {
  SoftSheet sheet(general);
  EXPECT_EQ(sheet.on_the_grid_path(), !general);
  MockSystem<double>& system = sheet.network.system();
  // The limits the plugin's tethers have, whatever is run: the untethered run is measured
  // against the same bound.
  const builtin::Tethers<double> expected = tethers_of(system, per_particle, 0.1);
  EXPECT_EQ(expected.slots(), per_particle);  // the nearest corner; both corners
  Integrator xpbd("xpbd");
  xpbd.with("inner_substeps", 2).with("tethers", tethers).with("tether_slack", 0.1);
  xpbd.start(system);
  double worst = 0;
  for (int n = 0; n < 200; ++n) {  // 2 s: the sheet falls, swings and sags
    EXPECT_EQ(xpbd.step(system, n * 0.01, 0.01), CLOTHLAB_OK) << xpbd.message();
    worst =
        std::max(worst, worst_tether_ratio(expected, system, SoftSheet::rows * SoftSheet::cols));
  }
  return worst;
}

TEST(XpbdTethers, HangingSheetStaysWithinTheSlackOfItsAnchors) {
  for (bool general : {false, true}) {
    EXPECT_GT(hang(general, 1, 0), 1.2) << "untethered, general path " << general;
    EXPECT_LE(hang(general, 1, 1), 1 + 1e-12) << "one tether, general path " << general;
    EXPECT_GT(hang(general, 2, 0), 1.2) << "untethered, general path " << general;
    // Two per particle, projected in turn once per substep: the second exactly, the first to
    // within what the second moves the particle (xpbd_tethers.hpp).
    EXPECT_LE(hang(general, 2, 2), 1.015) << "two tethers, general path " << general;
  }
}

TEST(XpbdTethers, APinnedEdgeTethersAboveAndBelow) {
  // A flag: the left column of a 9 x 6 grid pinned; one island, the pole.
  constexpr uint32_t rows = 9, cols = 6;
  std::vector<TestSpring> springs;
  std::vector<uint32_t> pole;
  for (uint32_t r = 0; r < rows; ++r) {
    pole.push_back(r * cols);
    for (uint32_t c = 0; c + 1 < cols; ++c)
      springs.push_back({r * cols + c, r * cols + c + 1, 1, 1, 0});
    if (r + 1 < rows)
      for (uint32_t c = 0; c < cols; ++c)
        springs.push_back({r * cols + c, (r + 1) * cols + c, 1, 1, 0});
  }
  SpringHost<double> network(rows * cols, pole, springs, {0, -g, 0});
  for (uint32_t r = 0; r < rows; ++r)
    for (uint32_t c = 0; c < cols; ++c)
      network.system().set_position(r * cols + c, {1.0 * c, -1.0 * r, 0});
  const builtin::Tethers<double> tethers = tethers_of(network.system(), 3, 0.0);
  ASSERT_EQ(tethers.slots(), 3u);
  const uint32_t particle = 3 * cols + 4;            // row 3, column 4
  EXPECT_EQ(tethers.anchor(0, particle), 3 * cols);  // the nearest pin first, then the ends
  EXPECT_EQ(tethers.anchor(1, particle), (rows - 1) * cols);
  EXPECT_EQ(tethers.anchor(2, particle), 0u);
  EXPECT_DOUBLE_EQ(tethers.limit(0, particle), 4.0);
  EXPECT_DOUBLE_EQ(tethers.limit(2, particle), 5.0);  // 3-4-5 to the top of the pole
  EXPECT_FALSE(std::isfinite(tethers.limit(0, 0)));   // a pin has none
}

TEST(XpbdTethers, NoPinsNoTethers) {
  SpringHost<double> network(2, {}, {{0, 1, 1.0, 1.0, 0.0}}, {0, -g, 0});
  EXPECT_FALSE(tethers_of(network.system(), 3, 0.0).active());
}

TEST(XpbdTethers, BadValuesAreOneLineErrors) {
  for (const auto& [name, value] : {std::pair<const char*, double>{"tethers", 17},
                                    {"tethers", -1},
                                    {"tethers", 1.5},
                                    {"tether_slack", -0.01},
                                    {"tether_slack", 1.5}}) {
    Integrator xpbd("xpbd");
    xpbd.with(name, value);
    EXPECT_EQ(xpbd.create(), CLOTHLAB_ERROR_INVALID_ARGUMENT) << name << " = " << value;
    EXPECT_NE(xpbd.message().find(std::string("parameter ") + name + " = "), std::string::npos)
        << xpbd.message();
    EXPECT_EQ(xpbd.message().find('\n'), std::string::npos) << xpbd.message();
  }
}

}  // namespace
}  // namespace clothlab::test
