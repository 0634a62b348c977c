// The threads extension: the thread count the cloth was given, "all" (0) resolved to what the
// engine runs a large cloud with, the same for a cloud small enough to run on one thread.
#include <clothlab/ext/threads.h>
#include <gtest/gtest.h>

#include "extension_support.hpp"

namespace clothlab {
namespace {

uint32_t threads_offered(const Cloth& cloth) {
  const clothlab_system& system = cloth.system();
  const auto& table =
      testing::host_extension<clothlab_threads_extension>(system, CLOTHLAB_EXT_THREADS);
  return table.count(system.context);
}

TEST(ThreadsExtension, OffersTheThreadCountTheClothWasGiven) {
  for (int threads : {1, 2, 3}) {
    PipelineOptions options;
    options.threads = threads;
    // 4x4: below parallel_from_particles, the engine itself steps it on one thread.
    const Cloth small(testing::busy_scene(4, 4), Precision::Float64, options);
    EXPECT_EQ(threads_offered(small), static_cast<uint32_t>(threads));
    EXPECT_EQ(small.threads(), 1);
  }
}

TEST(ThreadsExtension, AllThreadsIsWhatALargeCloudRunsWith) {
  const Cloth large(testing::busy_scene(80, 80), Precision::Float32, PipelineOptions{});
  ASSERT_GE(80u * 80u, parallel_from_particles);
  EXPECT_EQ(threads_offered(large), static_cast<uint32_t>(large.threads()));
  EXPECT_GE(threads_offered(large), 1u);
}

}  // namespace
}  // namespace clothlab
