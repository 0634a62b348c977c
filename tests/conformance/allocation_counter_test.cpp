#include "allocation_counter.hpp"

#include <gtest/gtest.h>

#include <cstdlib>

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
