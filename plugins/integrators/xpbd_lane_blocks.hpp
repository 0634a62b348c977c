// xpbd's general sweep on lanes, as the plugin sees it: a colour's springs in blocks of lanes
// (xpbd_color_blocks.hpp), of the SIMD target that runs here: the plugin's own copy (its
// build's flags) or, in a portable build, a wider target's (xpbd_color_blocks_target.cpp),
// chosen as the grid sweep's is (xpbd_grid_path.hpp). None where no target has float lanes:
// then the sweep projects one spring at a time.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <utility>
#include <vector>

#include "xpbd_constraint.hpp"

namespace clothlab::builtin {

// What a sweep projects with: the positions x + dx (stride floats per coordinate), the
// particles' inverse masses w (the springs' weights), the multipliers by slot; reset where
// `fresh`, not stored unless `keep` (the substep's last sweep needs none after it); the number
// of threads sharing each colour's blocks (thread_share).
struct LaneArrays {
  const float* x;
  float* dx;
  const float* w;
  float* lambda;
  std::size_t stride;
  float h, h_squared;
  bool fresh, keep;
  int threads;
};

// Thread `thread`'s part of a colour's blocks [begin, end) when `threads` threads share them,
// as a static schedule splits it (a colour's blocks are independent: any split gives the same
// bits).
inline std::pair<long, long> thread_share(long begin, long end, long thread, long threads) {
  return {begin + (end - begin) * thread / threads, begin + (end - begin) * (thread + 1) / threads};
}

class LaneBlocks {
 public:
  virtual ~LaneBlocks() = default;
  // springs: colour c's in [color_offsets[c], color_offsets[c + 1]), over particles
  // [0, particle_count), each colour's blocks shared by `threads` threads (thread_share).
  // find_runs false: every block gathered (what a test holds the runs against).
  virtual void build(const std::vector<Constraint<float>>& springs,
                     const std::vector<uint32_t>& color_offsets, uint32_t particle_count,
                     int threads, bool find_runs) = 0;
  // The multipliers' slots.
  virtual std::size_t slots() const = 0;
  // Colour c's blocks: [blocks_begin(c), blocks_begin(c + 1)).
  virtual long blocks_begin(std::size_t color) const = 0;
  // Projects blocks [begin, end).
  virtual void project(long begin, long end, const LaneArrays& arrays) const = 0;

  // What the tests check of block b: whether it loads and stores its windows of particles whole
  // (xpbd_color_blocks.hpp), those windows ([start, start + width) each; none where its ends
  // are gathered), and the particles its springs join.
  virtual bool whole_windows(std::size_t b) const = 0;
  virtual std::vector<std::pair<uint32_t, uint32_t>> windows(std::size_t b) const = 0;
  virtual std::vector<uint32_t> live_particles(std::size_t b) const = 0;
};

}  // namespace clothlab::builtin
