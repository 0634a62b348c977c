// How the threads of XPBD's grid sweep (xpbd.cpp) share a substep's rows: two bands, one
// wavefront going down from row 0 and one going up from the last row, each run by a team
// whose threads take turns along the band's phases.
//
// The bands do not split the rows in fixed halves: each starts with `reserve` rows of its
// own and claims more, as it goes, from the rows neither holds yet, an eighth of them at a
// time and at least one. A band on a slower core (a shared machine, another program on
// that core) ends with fewer rows, and both finish together instead of one waiting for the
// other at the barrier before the seam. Any split gives the same bits (xpbd.cpp).
#pragma once

#include <algorithm>
#include <atomic>
#include <cstdint>
#include <limits>
#include <thread>

namespace clothlab::builtin {

// A thread's wavefront progress, on its own cache line: its successor in the team spins on
// it. `completed` is published every few wavefront times; once the thread's band has no
// rows left, `ended_at` holds its count of wavefront times.
struct alignas(64) Progress {
  std::atomic<uint32_t> completed{0};
  std::atomic<uint32_t> ended_at{std::numeric_limits<uint32_t>::max()};

  void reset() {
    completed.store(0, std::memory_order_relaxed);
    ended_at.store(std::numeric_limits<uint32_t>::max(), std::memory_order_relaxed);
  }
  void end(uint32_t times) {
    completed.store(times, std::memory_order_release);
    ended_at.store(times, std::memory_order_release);
  }
};

// Waits until `predecessor` has completed wavefront time `time`; false when its band ended
// before that time.
inline bool wait_for(const Progress& predecessor, uint32_t time) {
  for (int spins = 0;; ++spins) {
    if (predecessor.completed.load(std::memory_order_acquire) > time) return true;
    // `completed` holds the final count before `ended_at` does.
    if (predecessor.ended_at.load(std::memory_order_acquire) <= time) return false;
    // The machine may be shared: after a short spin, give the core to the thread waited on.
    if (spins < 64) {
#if defined(__x86_64__)
      __builtin_ia32_pause();
#endif
    } else {
      std::this_thread::yield();
    }
  }
}

// The rows neither band holds yet; each band's first thread claims from them.
class RowClaims {
 public:
  // Before the parallel region: `rows` in all, `reserve` of them held by each band.
  void reset(uint32_t rows, uint32_t reserve) {
    rows_ = rows;
    claimed_.store(std::min(rows, 2 * reserve), std::memory_order_relaxed);
  }

  // More rows for the caller's band, 0 once none are left: an eighth of those left, at
  // least one. The counts granted, with both reserves, sum to `rows`. The bands touch rows
  // apart from each other whatever the split, so the claims order no memory.
  uint32_t claim() {
    uint32_t seen = claimed_.load(std::memory_order_relaxed);
    while (seen < rows_) {
      const uint32_t chunk = std::max<uint32_t>(1, (rows_ - seen) / 8);
      if (claimed_.compare_exchange_weak(seen, seen + chunk, std::memory_order_relaxed))
        return chunk;
    }
    return 0;
  }

 private:
  alignas(64) std::atomic<uint32_t> claimed_{0};
  uint32_t rows_ = 0;
};

}  // namespace clothlab::builtin
