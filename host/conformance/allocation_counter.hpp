// Counts heap allocations made by any thread of the process while armed, so a plugin that
// allocates in its own worker threads during step is seen as well as one that allocates in
// the calling thread. The runner interposes malloc, calloc, realloc, free, the aligned
// allocators and operator new/delete (as pluginval does).
#pragma once

#include <cstdint>

namespace clothlab::conformance::allocations {

void arm();
// Stops counting and returns the calls (allocations and frees) seen since arm().
uint64_t disarm();

// Suspends counting on this thread while the host's own code runs inside an armed region.
class Pause {
 public:
  Pause();
  ~Pause();
  Pause(const Pause&) = delete;
  Pause& operator=(const Pause&) = delete;

 private:
  bool was_paused_;
};

}  // namespace clothlab::conformance::allocations
