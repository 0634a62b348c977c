// The plugin tests' spring host (spring_host.hpp): against the extension registry (every host
// extension answered, once its grid and thread count are set, or declined by name), and its
// Jacobians against its own accelerations with unequal masses.
#include "spring_host.hpp"

#include <gtest/gtest.h>

#include <clothlab/core/extension_registry.hpp>
#include <cmath>
#include <vector>

namespace clothlab::test {
namespace {

TEST(SpringHost, AnswersOrDeclinesEveryHostExtension) {
  SpringHost<double> host(9, {0}, provot_net_springs(3, 3, 0.1, 100, 10, 0.1), {0, -9.81, 0});
  host.set_grid(3, 3, 0.1, {});
  host.set_threads(1);
  const clothlab_system& system = host.system().raw();
  EXPECT_EQ(extension_coverage(
                "the spring host", ExtensionSide::Host,
                [&](const char* id) { return system.get_extension(system.context, id); },
                SpringHost<double>::kDeclinedExtensions),
            "");
}

// With unequal masses the host's products are M^-1 times the spring forces' derivatives: the
// exact Jacobian's product matches central differences of its accelerations in x and in v, the
// definite form's M D is symmetric, and its diagonal blocks are its product's.
TEST(SpringHost, ItsJacobiansDivideByEachParticlesMass) {
  constexpr uint32_t kSide = 4, kCount = kSide * kSide;
  SpringHost<double> host(kCount, {0}, provot_net_springs(kSide, kSide, 0.1, 100, 10, 0.5),
                          {0, -9.81, 0});
  MockSystem<double>& mock = host.system();
  for (uint32_t i = 0; i < kCount; ++i) {
    mock.set_position(
        i, {0.11 * (i % kSide) + 0.01 * std::sin(i), 0.09 * (i / kSide), 0.02 * std::cos(3.0 * i)});
    mock.set_velocity(i, {0.1 * std::sin(2.0 * i), 0.2 * std::cos(i), 0.05 * i});
    mock.set_mass(i, 0.5 + 0.375 * (i % 5));
  }
  const clothlab_system& system = mock.raw();
  const auto& jacobian = *static_cast<const clothlab_jacobian_extension*>(
      system.get_extension(system.context, CLOTHLAB_EXT_JACOBIAN));
  const auto& definite = *static_cast<const clothlab_definite_jacobian_extension*>(
      system.get_extension(system.context, CLOTHLAB_EXT_DEFINITE_JACOBIAN));
  const std::size_t size = 3 * std::size_t{mock.stride()};
  const auto* x = static_cast<const double*>(system.x);
  const auto* v = static_cast<const double*>(system.v);
  const auto* inverse_mass = static_cast<const double*>(system.inverse_mass);
  std::vector<double> u(size), w(size), ju(size), jw(size), plus(size), minus(size), moved(size);
  for (std::size_t k = 0; k < size; ++k) {
    u[k] = std::sin(1.3 * k + 0.2);
    w[k] = std::cos(0.7 * k);
  }
  for (std::size_t d = 0; d < 3; ++d) u[d * mock.stride()] = w[d * mock.stride()] = 0.0;  // pinned
  const auto free_entries = [&](auto&& body) {
    for (uint32_t i = 1; i < kCount; ++i)
      for (std::size_t d = 0; d < 3; ++d) body(i, d * mock.stride() + i);
  };
  // Central differences of the accelerations along u, in x (c_x = 1) and in v (c_v = 1).
  for (const bool in_x : {true, false}) {
    const double step = 1e-6;
    const double* base = in_x ? x : v;
    for (const double sign : {1.0, -1.0}) {
      for (std::size_t k = 0; k < size; ++k) moved[k] = base[k] + sign * step * u[k];
      ASSERT_EQ(
          system.eval_acceleration(system.context, 0.0, in_x ? moved.data() : x,
                                   in_x ? v : moved.data(), sign > 0 ? plus.data() : minus.data()),
          CLOTHLAB_OK);
    }
    ASSERT_EQ(jacobian.apply(system.context, 0.0, x, v, in_x ? 1.0 : 0.0, in_x ? 0.0 : 1.0,
                             u.data(), ju.data()),
              CLOTHLAB_OK);
    double worst = 0.0, largest = 0.0;
    free_entries([&](uint32_t, std::size_t k) {
      worst = std::max(worst, std::abs(ju[k] - (plus[k] - minus[k]) / (2 * step)));
      largest = std::max(largest, std::abs(ju[k]));
    });
    ASSERT_GT(largest, 1.0);
    EXPECT_LT(worst, 1e-6 * largest) << (in_x ? "in x" : "in v");
  }
  // M D symmetric: w^T M D u = u^T M D w.
  definite.apply(system.context, 0.0, x, v, -1e-4, -1e-2, u.data(), ju.data());
  definite.apply(system.context, 0.0, x, v, -1e-4, -1e-2, w.data(), jw.data());
  double wmdu = 0.0, umdw = 0.0;
  free_entries([&](uint32_t i, std::size_t k) {
    wmdu += w[k] * ju[k] / inverse_mass[i];
    umdw += u[k] * jw[k] / inverse_mass[i];
  });
  ASSERT_GT(std::abs(wmdu), 1e-3);
  EXPECT_NEAR(wmdu, umdw, 1e-12 * std::abs(wmdu));
  // The diagonal blocks against the product's columns: D e_(i,c) read at row i.
  std::vector<double> blocks(9 * std::size_t{kCount}), unit(size, 0.0);
  definite.diagonal_blocks(system.context, 0.0, x, v, -1e-4, -1e-2, blocks.data());
  double worst = 0.0, largest = 0.0;
  for (const double value : blocks) largest = std::max(largest, std::abs(value));
  ASSERT_GT(largest, 1e-3);
  for (uint32_t i = 1; i < kCount; ++i)
    for (std::size_t c = 0; c < 3; ++c) {
      unit[c * mock.stride() + i] = 1.0;
      definite.apply(system.context, 0.0, x, v, -1e-4, -1e-2, unit.data(), ju.data());
      unit[c * mock.stride() + i] = 0.0;
      for (std::size_t r = 0; r < 3; ++r)
        worst = std::max(worst, std::abs(blocks[9 * i + 3 * r + c] - ju[r * mock.stride() + i]));
    }
  EXPECT_LT(worst, 1e-12 * largest);
}

}  // namespace
}  // namespace clothlab::test
