// Linked into the `kernels` test executables (tests/CMakeLists.txt), which a portable build
// registers once per SIMD target with CLOTHLAB_SIMD set: on a CPU without that target every
// test of the run is skipped, not failed. Any other value reaches the code under test.
#include <gtest/gtest.h>

#include <clothlab/sdk/simd_target.hpp>
#include <cstdlib>
#include <string_view>

namespace {

class SkipATargetTheCpuLacks : public ::testing::Environment {
 public:
  void SetUp() override {
    const char* value = std::getenv("CLOTHLAB_SIMD");
    const std::string_view target = value == nullptr ? "" : value;
    if ((target == "avx2" || target == "avx512") && !clothlab::sdk::cpu_runs_simd_target(target))
      GTEST_SKIP() << "CLOTHLAB_SIMD=" << target
                   << ": this CPU lacks the target (it has: " << clothlab::sdk::cpu_simd_features()
                   << ")";
  }
};

[[maybe_unused]] const ::testing::Environment* const kSkip =
    ::testing::AddGlobalTestEnvironment(new SkipATargetTheCpuLacks);

}  // namespace
