// eval_acceleration_at forms its stage state row by row inside the force pass. It must give
// exactly what eval_acceleration gives on that state built as whole vectors by copy +
// lincomb (pinned particles keep the base), and agree with the reference system's
// independent eval_acceleration_at.
#include <clothlab/plugin.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "cloth_test_support.hpp"
#include "reference_system.hpp"

namespace clothlab {
namespace {

constexpr uint32_t kMaxTerms = CLOTHLAB_COMBINATION_MAX_TERMS;

struct Case {
  uint32_t rows, cols;
  int threads;
};

std::string case_name(const ::testing::TestParamInfo<Case>& info) {
  return std::to_string(info.param.rows) + "x" + std::to_string(info.param.cols) + "_t" +
         std::to_string(info.param.threads);
}

// 10 g per particle on 1 m springs, damped, in wind; column 0 and two single particles
// pinned.
constexpr double kParticleMass = 0.01;
constexpr SpringFamily kStructural{50.0, 0.05}, kShear{20.0, 0.02}, kFlexion{5.0, 0.01};
// Sum of k / m over the springs at an interior particle (4 of each family).
constexpr double kSpringRate = 4 * (kStructural.ks + kShear.ks + kFlexion.ks) / kParticleMass;

Scene scene_for(const Case& c) {
  Scene scene = testing::bare_scene(c.rows, c.cols);
  const uint32_t n = c.rows * c.cols;
  scene.total_mass = kParticleMass * n;
  scene.structural = kStructural;
  scene.shear = kShear;
  scene.flexion = kFlexion;
  scene.gravity = {0.0, -9.81, 0.0};
  scene.wind_direction = {0.6, 0.0, 0.8};
  scene.wind_strength = 2.0;
  testing::add_pins(scene, true, true);
  return scene;
}

// Element (i, k) of the vectors of the test. Terms are nonzero on pinned particles too:
// the sums must ignore them there.
double base_position(std::size_t i, std::size_t k, uint32_t cols) {
  return testing::perturbed_layout(i, k, cols, 0.03);
}
double base_velocity(std::size_t i, std::size_t k) {
  return 0.3 * std::sin(0.9 * static_cast<double>(i) + 1.3 * k + 0.4);
}
double term(std::size_t j, std::size_t i, std::size_t k) {
  return std::sin(0.37 * static_cast<double>((j + 1) * i) + 1.1 * k + 0.7 * j);
}

// Coefficients of up to 9 terms (one past the limit, for the refusal); the position terms
// stay within a few cm of the base, so no spring comes near zero length.
constexpr std::array<double, kMaxTerms + 1> kPositionCoefficients{
    0.01, -0.008, 0.006, 0.005, -0.004, 0.003, -0.002, 0.002, 0.001};
constexpr std::array<double, kMaxTerms + 1> kVelocityCoefficients{0.2,  -0.15, 0.1,  0.08, -0.06,
                                                                  0.05, -0.04, 0.03, 0.02};

template <class Real>
Precision precision_of() {
  return sizeof(Real) == sizeof(float) ? Precision::Float32 : Precision::Float64;
}

// The vectors of one system filled with the test's values, and the callbacks on them.
template <class Real>
class Vectors {
 public:
  Vectors(const clothlab_system& system, uint32_t cols) : system_(system) {
    base_x_ = filled([&](std::size_t i, std::size_t k) { return base_position(i, k, cols); });
    base_v_ = filled([&](std::size_t i, std::size_t k) { return base_velocity(i, k); });
    for (std::size_t j = 0; j <= kMaxTerms; ++j) {
      x_terms_[j] = filled([&](std::size_t i, std::size_t k) { return term(j, i, k); });
      v_terms_[j] = filled([&](std::size_t i, std::size_t k) { return term(j + 20, i, k); });
    }
    x_ = system.alloc_vector(system.context);
    v_ = system.alloc_vector(system.context);
    a_ = system.alloc_vector(system.context);
  }

  clothlab_combination positions(uint32_t count) const {
    return {base_x_, count, 0, kPositionCoefficients.data(), x_terms_.data()};
  }
  clothlab_combination velocities(uint32_t count) const {
    return {base_v_, count, 0, kVelocityCoefficients.data(), v_terms_.data()};
  }

  // eval_acceleration_at on the sums; v_count < 0: v = NULL.
  clothlab_status at(uint32_t x_count, int v_count, std::vector<double>& a) {
    const clothlab_combination x = positions(x_count);
    const clothlab_combination v = velocities(v_count < 0 ? 0 : static_cast<uint32_t>(v_count));
    const clothlab_status status =
        system_.eval_acceleration_at(system_.context, 0.0, &x, v_count < 0 ? nullptr : &v, a_);
    a = read(a_);
    return status;
  }

  // The same state built as vectors with copy + lincomb, then eval_acceleration.
  clothlab_status formed_then_evaluated(uint32_t x_count, int v_count, std::vector<double>& a) {
    system_.copy(system_.context, x_, base_x_);
    system_.lincomb(system_.context, x_, base_x_, x_count, kPositionCoefficients.data(),
                    x_terms_.data());
    if (v_count >= 0) {
      system_.copy(system_.context, v_, base_v_);
      system_.lincomb(system_.context, v_, base_v_, static_cast<uint32_t>(v_count),
                      kVelocityCoefficients.data(), v_terms_.data());
    }
    const clothlab_status status =
        system_.eval_acceleration(system_.context, 0.0, x_, v_count < 0 ? nullptr : v_, a_);
    a = read(a_);
    return status;
  }

 private:
  template <class Value>
  void* filled(Value value) {
    void* vector = system_.alloc_vector(system_.context);
    for (std::size_t i = 0; i < system_.particle_count; ++i) {
      for (std::size_t k = 0; k < 3; ++k) {
        testing::element<Real>(vector, system_, i, k) = static_cast<Real>(value(i, k));
      }
    }
    return vector;
  }

  std::vector<double> read(void* vector) const {
    std::vector<double> out(3 * system_.particle_count);
    for (std::size_t i = 0; i < system_.particle_count; ++i) {
      for (std::size_t k = 0; k < 3; ++k) {
        out[3 * i + k] = testing::element<Real>(vector, system_, i, k);
      }
    }
    return out;
  }

  const clothlab_system& system_;
  const void* base_x_ = nullptr;
  const void* base_v_ = nullptr;
  std::array<const void*, kMaxTerms + 1> x_terms_{};
  std::array<const void*, kMaxTerms + 1> v_terms_{};
  void* x_ = nullptr;  // the formed state and the result
  void* v_ = nullptr;
  void* a_ = nullptr;
};

// Position and velocity term counts of the checks: every count 0..8 for each, paired in
// different ways so x and v cannot be mixed up unnoticed; -1 is v = NULL.
std::vector<std::array<int, 2>> term_counts() {
  std::vector<std::array<int, 2>> counts;
  for (int n = 0; n <= static_cast<int>(kMaxTerms); ++n) {
    counts.push_back({n, n});
    counts.push_back({n, static_cast<int>(kMaxTerms) - n});
    counts.push_back({n, -1});
  }
  return counts;
}

class StagedEval : public ::testing::TestWithParam<Case> {};

// Both paths sum the same terms in the same order per element and run the same force
// pass on the result, so they agree bit for bit.
template <class Real>
void expect_same_as_formed_state(const Case& c) {
  Cloth cloth(scene_for(c), precision_of<Real>(), {true, c.threads});
  Vectors<Real> vectors(cloth.system(), c.cols);
  std::vector<double> staged, formed, damped;
  for (const auto& [x_count, v_count] : term_counts()) {
    SCOPED_TRACE("x terms " + std::to_string(x_count) + ", v terms " + std::to_string(v_count));
    ASSERT_EQ(vectors.at(static_cast<uint32_t>(x_count), v_count, staged), CLOTHLAB_OK);
    ASSERT_EQ(vectors.formed_then_evaluated(static_cast<uint32_t>(x_count), v_count, formed),
              CLOTHLAB_OK);
    EXPECT_EQ(staged, formed);
  }
  // Damping acts in this scene, so the comparisons with v = NULL above saw it left out.
  ASSERT_EQ(vectors.at(3, 3, damped), CLOTHLAB_OK);
  ASSERT_EQ(vectors.at(3, -1, staged), CLOTHLAB_OK);
  EXPECT_NE(staged, damped);
}

TEST_P(StagedEval, EqualsEvaluationOfTheFormedStateInFloat64) {
  expect_same_as_formed_state<double>(GetParam());
}

TEST_P(StagedEval, EqualsEvaluationOfTheFormedStateInFloat32) {
  expect_same_as_formed_state<float>(GetParam());
}

// Each side rounds the spring vectors between positions of size max |x| (the grid is as
// wide as its columns): an error of eps * max |x| that springs turn into accelerations of
// up to eps * kSpringRate * max |x|, which bounds what summation order, contraction and the
// float kernels' 1/sqrt estimate + Newton step change. Measured with AVX-512's 14-bit
// estimate: at most 0.25 of it (AVX2's 12-bit one passes it too).
constexpr double kRoundOffBound = 2.0;

template <class Real>
void expect_agreement_with_reference(const Case& c) {
  const Scene scene = scene_for(c);
  Cloth cloth(scene, precision_of<Real>(), {true, c.threads});
  reference::ReferenceSystem<Real> baseline(scene, true);
  Vectors<Real> fast(cloth.system(), c.cols);
  Vectors<Real> slow(baseline.system(), c.cols);
  double largest_position = 0.0;
  for (std::size_t i = 0; i < scene.rows * scene.cols; ++i) {
    for (std::size_t k = 0; k < 3; ++k) {
      largest_position = std::max(largest_position, std::abs(base_position(i, k, c.cols)) + 0.05);
    }
  }
  std::vector<double> got, expected;
  for (const auto& [x_count, v_count] : term_counts()) {
    SCOPED_TRACE("x terms " + std::to_string(x_count) + ", v terms " + std::to_string(v_count));
    ASSERT_EQ(fast.at(static_cast<uint32_t>(x_count), v_count, got), CLOTHLAB_OK);
    ASSERT_EQ(slow.at(static_cast<uint32_t>(x_count), v_count, expected), CLOTHLAB_OK);
    double largest_acceleration = 0.0;
    for (double value : expected)
      largest_acceleration = std::max(largest_acceleration, std::abs(value));
    const double bound = kRoundOffBound * std::numeric_limits<Real>::epsilon() *
                         (largest_acceleration + kSpringRate * largest_position);
    for (std::size_t e = 0; e < expected.size(); ++e) {
      ASSERT_NEAR(got[e], expected[e], bound)
          << "particle " << e / 3 << " (row " << e / 3 / c.cols << ", col " << e / 3 % c.cols
          << "), component " << e % 3;
    }
  }
}

TEST_P(StagedEval, AgreesWithTheReferenceInFloat64) {
  expect_agreement_with_reference<double>(GetParam());
}

TEST_P(StagedEval, AgreesWithTheReferenceInFloat32) {
  expect_agreement_with_reference<float>(GetParam());
}

// The engine threads from 4096 particles: 70 x 70 runs on 2 and 3 threads.
INSTANTIATE_TEST_SUITE_P(Grids, StagedEval,
                         ::testing::Values(Case{1, 7, 1}, Case{5, 4, 1}, Case{17, 13, 1},
                                           Case{70, 70, 2}, Case{70, 70, 3}, Case{4100, 2, 2},
                                           Case{300, 15, 3}),
                         case_name);

template <class Real>
void expect_nine_terms_refused() {
  const Case c{5, 4, 1};
  Cloth cloth(scene_for(c), precision_of<Real>(), {true, 1});
  Vectors<Real> vectors(cloth.system(), c.cols);
  std::vector<double> a;
  EXPECT_EQ(vectors.at(kMaxTerms + 1, 0, a), CLOTHLAB_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(vectors.at(0, kMaxTerms + 1, a), CLOTHLAB_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(vectors.at(kMaxTerms, kMaxTerms, a), CLOTHLAB_OK);
}

TEST(StagedEvalRefusals, NineTermsAreInvalid) {
  expect_nine_terms_refused<double>();
  expect_nine_terms_refused<float>();
}

}  // namespace
}  // namespace clothlab
