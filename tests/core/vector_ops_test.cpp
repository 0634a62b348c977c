// axpy, lincomb and copy act on active particles only (copy on all) and count their work.
#include <gtest/gtest.h>

#include "cloth_test_support.hpp"

namespace clothlab {
namespace {

template <class Real>
class VectorOps : public ::testing::Test {
 protected:
  VectorOps() : cloth_(pinned_scene(), precision(), {}), system_(cloth_.system()) {}

  static Scene pinned_scene() {
    Scene scene = testing::bare_scene(90, 60);  // large enough to run threaded
    scene.pinned = {0, 59, 3000};
    return scene;
  }
  static Precision precision() {
    return sizeof(Real) == sizeof(float) ? Precision::Float32 : Precision::Float64;
  }
  // A vector whose element (i, k) is value(i, k).
  void* filled(double (*value)(std::size_t, std::size_t)) {
    void* vector = system_.alloc_vector(system_.context);
    for (std::size_t i = 0; i < system_.particle_count; ++i) {
      for (std::size_t k = 0; k < 3; ++k) {
        testing::element<Real>(vector, system_, i, k) = static_cast<Real>(value(i, k));
      }
    }
    return vector;
  }
  bool pinned(std::size_t i) const { return i == 0 || i == 59 || i == 3000; }
  Real at(void* vector, std::size_t i, std::size_t k) {
    return testing::element<Real>(vector, system_, i, k);
  }

  Cloth cloth_;
  const clothlab_system& system_;
};
using Precisions = ::testing::Types<float, double>;
TYPED_TEST_SUITE(VectorOps, Precisions);

double index_value(std::size_t i, std::size_t k) { return static_cast<double>(i % 97) + k; }
double one(std::size_t, std::size_t) { return 1.0; }
double two(std::size_t, std::size_t) { return 2.0; }

TYPED_TEST(VectorOps, AxpySkipsPinned) {
  void* y = this->filled(&one);
  void* x = this->filled(&index_value);
  this->system_.axpy(this->system_.context, y, 0.5, x);
  for (std::size_t i = 0; i < this->system_.particle_count; ++i) {
    for (std::size_t k = 0; k < 3; ++k) {
      const double expected = this->pinned(i) ? 1.0 : 1.0 + 0.5 * index_value(i, k);
      ASSERT_EQ(this->at(y, i, k), static_cast<TypeParam>(expected)) << i << "," << k;
    }
  }
  EXPECT_EQ(this->cloth_.counters().particles_integrated, 5400u - 3u);
}

TYPED_TEST(VectorOps, LincombWithOutputAliasingAnInput) {
  void* base = this->filled(&one);
  void* first = this->filled(&index_value);
  void* second = this->filled(&two);
  const double coefficients[] = {2.0, -0.25};
  const void* vectors[] = {first, second};
  // out = second: every element must be read before it is overwritten.
  this->system_.lincomb(this->system_.context, second, base, 2, coefficients, vectors);
  for (std::size_t i = 0; i < this->system_.particle_count; ++i) {
    for (std::size_t k = 0; k < 3; ++k) {
      const double expected = this->pinned(i) ? 2.0 : 1.0 + 2.0 * index_value(i, k) - 0.5;
      ASSERT_EQ(this->at(second, i, k), static_cast<TypeParam>(expected)) << i << "," << k;
    }
  }
  this->system_.lincomb(this->system_.context, base, base, 0, nullptr, nullptr);
  EXPECT_EQ(this->at(base, 1, 0), TypeParam(1));
  EXPECT_EQ(this->cloth_.counters().particles_integrated, 2 * (5400u - 3u));
}

TYPED_TEST(VectorOps, CopyIncludesPinned) {
  void* source = this->filled(&index_value);
  void* target = this->filled(&one);
  this->system_.copy(this->system_.context, target, source);
  for (std::size_t i = 0; i < this->system_.particle_count; ++i) {
    for (std::size_t k = 0; k < 3; ++k) ASSERT_EQ(this->at(target, i, k), this->at(source, i, k));
  }
}

TYPED_TEST(VectorOps, ResetCountersStartsFromZero) {
  void* y = this->filled(&one);
  this->system_.axpy(this->system_.context, y, 1.0, y);
  this->cloth_.reset_counters();
  EXPECT_EQ(this->cloth_.counters().particles_integrated, 0u);
}

}  // namespace
}  // namespace clothlab
