#include "allocation_counter.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <cstdlib>
#include <thread>

using namespace clothlab::conformance;

namespace {
// Opaque to the optimiser, so the allocations below really happen.
void* volatile sink;
}  // namespace

TEST(AllocationCounter, CountsMallocFreeAndNewWhileArmed) {
  allocations::arm();
  sink = std::malloc(16);
  std::free(sink);
  int* numbers = new int[4];
  sink = numbers;
  delete[] numbers;
  EXPECT_EQ(allocations::disarm(), 4u);  // malloc, free, new[], delete[]
}

TEST(AllocationCounter, IgnoresAllocationsWhileDisarmedOrPaused) {
  sink = std::malloc(16);
  std::free(sink);
  allocations::arm();
  {
    const allocations::Pause pause;
    sink = std::malloc(16);
    std::free(sink);
  }
  EXPECT_EQ(allocations::disarm(), 0u);
}

// A worker started before arming allocates while the arming thread is paused: counted, since a
// plugin's own threads are not the host's.
TEST(AllocationCounter, CountsAllocationsOfOtherThreads) {
  std::atomic<int> stage{0};
  std::thread worker([&] {
    while (stage.load() != 1) std::this_thread::yield();
    sink = std::malloc(16);
    std::free(sink);
    stage.store(2);
  });
  allocations::arm();
  {
    const allocations::Pause pause;  // pauses this thread only
    stage.store(1);
    while (stage.load() != 2) std::this_thread::yield();
  }
  EXPECT_EQ(allocations::disarm(), 2u);  // the worker's malloc and free
  worker.join();
}
