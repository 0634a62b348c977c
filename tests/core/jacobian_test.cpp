// The jacobian extension against central finite differences of eval_acceleration (float64,
// no wind: its x-dependence is left out by contract), with damping on, pinned particles
// and a state off rest; the block forms against the matrix-free product; float32 against
// float64; the same bits on one and several threads.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "extension_support.hpp"

namespace clothlab {
namespace {

using testing::host_extension;
using testing::max_abs;
using testing::max_difference;
using testing::values_of;
using testing::vector_from;

Scene windless(uint32_t rows, uint32_t cols) {
  Scene scene = testing::busy_scene(rows, cols);
  scene.wind_strength = 0.0;
  return scene;
}

// A float64 cloth off rest with a direction u (zero on pinned particles) and the Jacobian.
struct Linearisation {
  explicit Linearisation(const Scene& scene, PipelineOptions options = {})
      : cloth(scene, Precision::Float64, options), system(cloth.system()) {
    testing::move_off_rest(cloth, 7, 0.05, x, v);
    std::vector<double> direction(x.size());
    for (std::size_t e = 0; e < direction.size(); ++e)
      direction[e] = std::sin(0.37 * static_cast<double>(e) + 0.1);
    for (uint32_t pinned : scene.pinned)
      for (std::size_t k = 0; k < 3; ++k) direction[3 * pinned + k] = 0;
    u = direction;
    jacobian = &host_extension<clothlab_jacobian_extension>(system, CLOTHLAB_EXT_JACOBIAN);
    EXPECT_EQ(jacobian->reserve(system.context), CLOTHLAB_OK);
  }

  std::vector<double> acceleration(const std::vector<double>& at_x,
                                   const std::vector<double>* at_v) {
    void* xs = vector_from<double>(system, at_x);
    void* vs = at_v ? vector_from<double>(system, *at_v) : nullptr;
    void* a = system.alloc_vector(system.context);
    EXPECT_EQ(system.eval_acceleration(system.context, 0.0, xs, vs, a), CLOTHLAB_OK);
    return values_of<double>(system, a);
  }

  // (a(q + h u) - a(q - h u)) / 2h along x (along_x) or v.
  std::vector<double> central_difference(bool along_x, bool with_velocity, double h) {
    std::vector<double> plus = along_x ? x : v, minus = plus;
    for (std::size_t e = 0; e < u.size(); ++e) {
      plus[e] += h * u[e];
      minus[e] -= h * u[e];
    }
    const std::vector<double> a_plus =
        along_x ? acceleration(plus, with_velocity ? &v : nullptr) : acceleration(x, &plus);
    const std::vector<double> a_minus =
        along_x ? acceleration(minus, with_velocity ? &v : nullptr) : acceleration(x, &minus);
    std::vector<double> out(u.size());
    for (std::size_t e = 0; e < out.size(); ++e) out[e] = (a_plus[e] - a_minus[e]) / (2 * h);
    return out;
  }

  std::vector<double> apply(double c_x, double c_v, bool with_velocity) {
    void* xs = vector_from<double>(system, x);
    void* vs = with_velocity ? vector_from<double>(system, v) : nullptr;
    void* us = vector_from<double>(system, u);
    void* out = system.alloc_vector(system.context);
    EXPECT_EQ(jacobian->apply(system.context, 0.0, xs, vs, c_x, c_v, us, out), CLOTHLAB_OK);
    return values_of<double>(system, out);
  }

  Cloth cloth;
  const clothlab_system& system;
  std::vector<double> x, v, u;
  const clothlab_jacobian_extension* jacobian = nullptr;
};

TEST(Jacobian, MatchesCentralDifferencesInPositionAndVelocity) {
  for (const auto& shape : {std::array<uint32_t, 2>{6, 7}, {2, 1}, {1, 5}, {13, 9}}) {
    SCOPED_TRACE(::testing::Message() << shape[0] << "x" << shape[1]);
    Linearisation l(windless(shape[0], shape[1]));
    const std::vector<double> dadx = l.apply(1.0, 0.0, true);
    const std::vector<double> dadv = l.apply(0.0, 1.0, true);
    const std::vector<double> fd_x = l.central_difference(true, true, 1e-6);
    const std::vector<double> fd_v = l.central_difference(false, true, 1e-6);
    ASSERT_GT(max_abs(fd_x), 1.0);
    EXPECT_LT(max_difference(dadx, fd_x), 1e-6 * max_abs(fd_x));
    EXPECT_LT(max_difference(dadv, fd_v), 1e-6 * max_abs(fd_v));
    // The weights combine linearly.
    const std::vector<double> both = l.apply(0.3, -2.0, true);
    for (std::size_t e = 0; e < both.size(); ++e)
      EXPECT_NEAR(both[e], 0.3 * dadx[e] - 2.0 * dadv[e], 1e-9 * max_abs(fd_x));
  }
}

TEST(Jacobian, TheDampingForcesPositionDependenceIsIncludedAndTheCheckSeesIt) {
  // A mutant dropping that term equals the product without velocities (v = NULL removes
  // the damping terms): the finite-difference check must tell the two apart by far.
  Linearisation l(windless(6, 7));
  const std::vector<double> fd_x = l.central_difference(true, true, 1e-6);
  const std::vector<double> exact = l.apply(1.0, 0.0, true);
  const std::vector<double> without_damping_term = l.apply(1.0, 0.0, false);
  const double term = max_difference(exact, without_damping_term);
  EXPECT_GT(term, 1e-3 * max_abs(fd_x));
  EXPECT_LT(max_difference(exact, fd_x), 1e-3 * term);
  EXPECT_GT(max_difference(without_damping_term, fd_x), 0.5 * term);
}

TEST(Jacobian, WithoutVelocitiesItIsTheHookeJacobianAndHasNoVelocityPart) {
  Linearisation l(windless(5, 6));
  const std::vector<double> fd_x = l.central_difference(true, false, 1e-6);
  EXPECT_LT(max_difference(l.apply(1.0, 0.0, false), fd_x), 1e-6 * max_abs(fd_x));
  EXPECT_EQ(max_abs(l.apply(0.0, 1.0, false)), 0.0);
}

TEST(Jacobian, WithoutVelocityForcesInTheEngineThereIsNoDampingTerm) {
  PipelineOptions options;
  options.velocity_forces = false;
  Linearisation l(windless(5, 6), options);
  EXPECT_EQ(max_abs(l.apply(0.0, 1.0, true)), 0.0);
  EXPECT_EQ(l.apply(1.0, 0.0, true), l.apply(1.0, 0.0, false));
}

TEST(Jacobian, PinnedRowsAreZeroAndPinnedEntriesOfUAreIgnored) {
  const Scene scene = windless(6, 7);
  Linearisation l(scene);
  const std::vector<double> clean = l.apply(0.7, 0.2, true);
  for (uint32_t pinned : scene.pinned)
    for (std::size_t k = 0; k < 3; ++k) {
      EXPECT_EQ(clean[3 * pinned + k], 0.0);
      l.u[3 * pinned + k] = 1e3;
    }
  EXPECT_EQ(l.apply(0.7, 0.2, true), clean);
}

TEST(Jacobian, DiagonalAndBlockMatrixReproduceTheProduct) {
  const Scene scene = windless(5, 4);
  Linearisation l(scene);
  const clothlab_system& system = l.system;
  const uint32_t n = system.particle_count;
  clothlab_block_pattern pattern{};
  pattern.struct_size = sizeof pattern;
  ASSERT_EQ(l.jacobian->pattern(system.context, &pattern), CLOTHLAB_OK);
  ASSERT_EQ(pattern.row_count, n);
  ASSERT_EQ(pattern.block_count, pattern.row_offsets[n]);
  void* xs = vector_from<double>(system, l.x);
  void* vs = vector_from<double>(system, l.v);
  std::vector<double> values(9 * std::size_t{pattern.block_count}), diagonal(9 * std::size_t{n});
  ASSERT_EQ(l.jacobian->blocks(system.context, 0.0, xs, vs, 0.6, 0.4, values.data()), CLOTHLAB_OK);
  ASSERT_EQ(l.jacobian->diagonal_blocks(system.context, 0.0, xs, vs, 0.6, 0.4, diagonal.data()),
            CLOTHLAB_OK);
  const std::vector<double> product = l.apply(0.6, 0.4, true);
  std::vector<double> assembled(3 * std::size_t{n}, 0.0);
  for (uint32_t i = 0; i < n; ++i) {
    bool has_diagonal = false;
    for (uint32_t b = pattern.row_offsets[i]; b < pattern.row_offsets[i + 1]; ++b) {
      const uint32_t j = pattern.columns[b];
      if (b > pattern.row_offsets[i]) {
        EXPECT_LT(pattern.columns[b - 1], j);
      }
      if (j == i) {
        has_diagonal = true;
        for (std::size_t e = 0; e < 9; ++e)
          EXPECT_NEAR(values[9 * b + e], diagonal[9 * i + e],
                      1e-12 * std::abs(diagonal[9 * i + e]));
      }
      for (std::size_t r = 0; r < 3; ++r)
        for (std::size_t c = 0; c < 3; ++c)
          assembled[3 * i + r] += values[9 * b + 3 * r + c] * l.u[3 * j + c];
    }
    EXPECT_TRUE(has_diagonal) << i;
  }
  EXPECT_LT(max_difference(assembled, product), 1e-12 * max_abs(product));
  EXPECT_GT(max_abs(product), 0.0);
}

TEST(Jacobian, Float32AgreesWithFloat64) {
  const Scene scene = windless(6, 7);
  Linearisation wide(scene);
  Cloth cloth(scene, Precision::Float32, {});
  cloth.set_state(wide.x, wide.v);
  const clothlab_system& system = cloth.system();
  const auto& jacobian = host_extension<clothlab_jacobian_extension>(system, CLOTHLAB_EXT_JACOBIAN);
  void* u = vector_from<float>(system, wide.u);
  void* out = system.alloc_vector(system.context);
  ASSERT_EQ(jacobian.apply(system.context, 0.0, system.x, system.v, 1.0, 0.5, u, out), CLOTHLAB_OK);
  const std::vector<double> wide_product = wide.apply(1.0, 0.5, true);
  EXPECT_LT(max_difference(values_of<float>(system, out), wide_product),
            1e-5 * max_abs(wide_product));
}

TEST(Jacobian, SameBitsOnOneAndSeveralThreads) {
  const Scene scene = windless(80, 70);  // large enough to run threaded
  std::vector<double> reference;
  for (int threads : {1, 2, 3}) {
    PipelineOptions options;
    options.threads = threads;
    Linearisation l(scene, options);
    const std::vector<double> product = l.apply(1.0, 0.1, true);
    if (reference.empty()) {
      reference = product;
    } else {
      EXPECT_EQ(product, reference) << threads << " threads";
    }
  }
}

}  // namespace
}  // namespace clothlab
