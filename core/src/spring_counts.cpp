#include <algorithm>
#include <clothlab/core/cloth.hpp>

namespace clothlab {

SpringCounts count_springs(uint32_t rows, uint32_t cols) {
  const uint64_t r = rows;
  const uint64_t c = cols;
  SpringCounts counts;
  if (r == 0 || c == 0) return counts;
  counts.structural = r * (c - 1) + c * (r - 1);
  counts.shear = 2 * (r - 1) * (c - 1);
  // A flexion spring spans two cells, so it needs at least three particles in a line.
  counts.flexion = r * (std::max<uint64_t>(c, 2) - 2) + c * (std::max<uint64_t>(r, 2) - 2);
  return counts;
}

}  // namespace clothlab
