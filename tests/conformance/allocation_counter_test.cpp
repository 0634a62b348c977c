#include "allocation_counter.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <cstdlib>
#include <thread>

#include "../support/sanitizer.hpp"

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
    // Ending the thread frees its start-up state: only once the counter is disarmed.
    while (stage.load() != 3) std::this_thread::yield();
  });
  allocations::arm();
  {
    const allocations::Pause pause;  // pauses this thread only
    stage.store(1);
    while (stage.load() != 2) std::this_thread::yield();
  }
  const uint64_t calls = allocations::disarm();
  stage.store(3);
  worker.join();
  // The worker's malloc and free; in a sanitizer build the runtime's own bookkeeping for the
  // thread is counted through its allocation hooks as well.
  if (clothlab::testing::address_sanitizer) {
    EXPECT_GE(calls, 2u);
  } else {
    EXPECT_EQ(calls, 2u);
  }
}
