// How the threads of XPBD's grid sweep (xpbd_grid_sweep.hpp) share a substep's rows: two
// bands, one wavefront going down from row 0 and one going up from the last row, each run by
// a team whose threads take turns along the band's phases (xpbd_wavefront.hpp).
//
// The bands do not split the rows in fixed halves: each starts with `reserve` rows of its
// own and claims more, as it goes, from the rows neither holds yet, an eighth of them at a
// time and at least one. A band on a slower core (a shared machine, another program on
// that core) ends with fewer rows, and both finish together instead of one waiting for the
// other at the barrier before the seam. Any split gives the same bits (xpbd_grid_sweep.hpp).
#pragma once

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <span>
#include <thread>
#include <utility>

#include "xpbd_wavefront.hpp"

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

// One turn of a spin: tells the core the thread is waiting, where the instruction exists.
inline void spin_pause() {
#if defined(__x86_64__)
  __builtin_ia32_pause();
#endif
}

// Spins until `done()`. The machine may be shared: after a short spin it gives the core to the
// thread waited on.
template <class Done>
inline void spin_until(Done&& done) {
  for (int spins = 0; !done(); ++spins) {
    if (spins < 64)
      spin_pause();
    else
      std::this_thread::yield();
  }
}

// Waits until `predecessor` has completed wavefront time `time`; false when its band ended
// before that time.
inline bool wait_for(const Progress& predecessor, uint32_t time) {
  bool completed = false;
  spin_until([&] {
    completed = predecessor.completed.load(std::memory_order_acquire) > time;
    // `completed` holds the final count before `ended_at` does.
    return completed || predecessor.ended_at.load(std::memory_order_acquire) <= time;
  });
  return completed;
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

// The seam's two units of one phase, the rows below the boundary and those above: each is
// claimed by whichever of the two bands' first threads comes to it first, so that a thread
// whose partner is descheduled does its partner's unit instead of waiting for it. Only a
// unit claimed and still running is waited for. The rows of a phase are the same whoever
// runs them: the bits do not change.
struct alignas(64) SeamUnits {
  enum : uint32_t { kOpen = 0, kClaimed = 1, kDone = 2 };
  std::atomic<uint32_t> state[2] = {kOpen, kOpen};

  void reset() {
    for (auto& unit : state) unit.store(kOpen, std::memory_order_relaxed);
  }
  // Whether the caller took unit `side` (and must run it, then call done).
  bool claim(int side) {
    if (state[side].load(std::memory_order_relaxed) != kOpen) return false;
    uint32_t open = kOpen;
    return state[side].compare_exchange_strong(open, kClaimed, std::memory_order_acquire);
  }
  void done(int side) { state[side].store(kDone, std::memory_order_release); }
  // Spins a little while unit `side` is open.
  void settle(int side) const {
    for (int spins = 0; spins < 256 && state[side].load(std::memory_order_relaxed) == kOpen;
         ++spins)
      spin_pause();
  }
  void wait(int side) const {
    spin_until([&] { return state[side].load(std::memory_order_acquire) == kDone; });
  }
};

// The teams of the grid sweep: two bands, the one going down run by threads
// [0, lower_threads), or one band of all threads.
struct Bands {
  bool two;
  int lower_threads;
};

// The rows a band holds from the start: one more than the wavefront's total lag, so that
// every phase visits at least one row of each band and the seam is all that is left.
inline uint32_t band_reserve(std::span<const Phase> phases) { return phases.back().lag + 1; }

// Two bands, one per half of the threads, when the rows hold both reserves (else one
// band and the seam would be all of it); one band on one thread.
inline Bands bands_of(int threads, uint32_t rows, uint32_t reserve) {
  if (threads < 2 || rows < 2 * reserve) return {false, threads};
  return {true, (threads + 1) / 2};
}

// Phases [begin, end) of `thread` among `threads`: contiguous runs of about equal cost.
inline std::pair<std::size_t, std::size_t> phases_of(std::span<const Phase> phases, int thread,
                                                     int threads) {
  uint64_t total = 0;
  for (const Phase& phase : phases) total += phase.cost;
  std::size_t begin = phases.size(), end = 0;
  uint64_t before = 0;
  for (std::size_t q = 0; q < phases.size(); ++q) {
    const uint64_t middle = 2 * before + phases[q].cost;  // twice the phase's midpoint
    const auto owner = static_cast<int>(std::min<uint64_t>(
        static_cast<uint64_t>(threads - 1), middle * static_cast<uint64_t>(threads) / (2 * total)));
    if (owner == thread) begin = std::min(begin, q), end = q + 1;
    before += phases[q].cost;
  }
  return {std::min(begin, end), end};
}

}  // namespace clothlab::builtin
