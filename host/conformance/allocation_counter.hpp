// Counts heap allocations made by the calling thread while armed. The runner interposes
// malloc, calloc, realloc, free, the aligned allocators and operator new/delete (as
// pluginval does), so allocations inside a plugin's step are seen too.
#pragma once

#include <cstdint>

namespace clothlab::conformance::allocations {

void arm();
// Stops counting and returns the calls (allocations and frees) seen since arm().
uint64_t disarm();

// Suspends counting while the host's own code runs inside an armed region.
class Pause {
 public:
  Pause();
  ~Pause();
  Pause(const Pause&) = delete;
  Pause& operator=(const Pause&) = delete;

 private:
  bool was_armed_;
};

}  // namespace clothlab::conformance::allocations
