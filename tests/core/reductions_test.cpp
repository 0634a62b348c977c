// The reductions extension against plain loops over the active particles (pinned entries
// hold values that must be ignored), its NaN reporting and the same bits on any number of
// threads.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "extension_support.hpp"

namespace clothlab {
namespace {

using testing::host_extension;
using testing::vector_from;

template <class Real>
void expect_plain_loop_results(Precision precision) {
  const Scene scene = testing::busy_scene(9, 13);
  Cloth cloth(scene, precision, {});
  const clothlab_system& system = cloth.system();
  const auto& reductions =
      host_extension<clothlab_reductions_extension>(system, CLOTHLAB_EXT_REDUCTIONS);
  const std::size_t n = system.particle_count;
  std::vector<double> a(3 * n), b(3 * n);
  for (std::size_t e = 0; e < 3 * n; ++e) {
    a[e] = static_cast<Real>(std::sin(0.3 * static_cast<double>(e)));
    b[e] = static_cast<Real>(std::cos(0.7 * static_cast<double>(e)) - 0.2);
  }
  for (uint32_t pinned : scene.pinned) a[3 * pinned] = b[3 * pinned] = 1e6;  // ignored
  const std::vector<double> inverse_mass = testing::inverse_masses<Real>(system);
  double dot = 0, mass_dot = 0, max_abs = 0;
  for (std::size_t i = 0; i < n; ++i) {
    if (inverse_mass[i] == 0) continue;
    for (std::size_t k = 0; k < 3; ++k) {
      dot += a[3 * i + k] * b[3 * i + k];
      mass_dot += a[3 * i + k] * b[3 * i + k] / inverse_mass[i];
      max_abs = std::max(max_abs, std::abs(a[3 * i + k]));
    }
  }
  void* va = vector_from<Real>(system, a);
  void* vb = vector_from<Real>(system, b);
  EXPECT_NEAR(reductions.dot(system.context, va, vb), dot, 1e-12 * n);
  EXPECT_NEAR(reductions.mass_dot(system.context, va, vb), mass_dot,
              1e-12 * n * std::abs(mass_dot));
  EXPECT_EQ(reductions.max_abs(system.context, va), max_abs);
  EXPECT_LT(max_abs, 1e6);
}

TEST(Reductions, MatchPlainLoopsOverTheActiveParticlesFloat64) {
  expect_plain_loop_results<double>(Precision::Float64);
}

TEST(Reductions, MatchPlainLoopsOverTheActiveParticlesFloat32) {
  expect_plain_loop_results<float>(Precision::Float32);
}

TEST(Reductions, MaxAbsReportsANaN) {
  Cloth cloth(testing::busy_scene(4, 4), Precision::Float64, {});
  const clothlab_system& system = cloth.system();
  const auto& reductions =
      host_extension<clothlab_reductions_extension>(system, CLOTHLAB_EXT_REDUCTIONS);
  std::vector<double> a(48, 1.0);
  a[3 * 5 + 1] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_TRUE(std::isnan(reductions.max_abs(system.context, vector_from<double>(system, a))));
}

TEST(Reductions, SameBitsForAnyThreadCount) {
  const Scene scene = testing::busy_scene(100, 90);  // large enough to run threaded
  double dot = 0, mass_dot = 0;
  for (int threads : {1, 2, 3, 4}) {
    PipelineOptions options;
    options.threads = threads;
    Cloth cloth(scene, Precision::Float32, options);
    const clothlab_system& system = cloth.system();
    const auto& reductions =
        host_extension<clothlab_reductions_extension>(system, CLOTHLAB_EXT_REDUCTIONS);
    std::vector<double> a(3 * std::size_t{system.particle_count});
    for (std::size_t e = 0; e < a.size(); ++e) a[e] = std::sin(1e-3 * static_cast<double>(e * e));
    void* va = vector_from<float>(system, a);
    const double d = reductions.dot(system.context, va, system.x);
    const double m = reductions.mass_dot(system.context, va, va);
    if (threads == 1) {
      dot = d;
      mass_dot = m;
    } else {
      EXPECT_EQ(d, dot) << threads << " threads";
      EXPECT_EQ(m, mass_dot) << threads << " threads";
    }
  }
}

}  // namespace
}  // namespace clothlab
