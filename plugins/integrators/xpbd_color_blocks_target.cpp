// xpbd's general sweep's lane blocks as one SIMD target's entry point,
// make_color_blocks_<target> (xpbd_general_sweep.hpp), compiled once per wider target of a
// portable build.
#include "simd_namespace.hpp"
#include "xpbd_color_blocks.hpp"

namespace clothlab::builtin {

std::unique_ptr<LaneBlocks> CLOTHLAB_SIMD_ENTRY(make_color_blocks)() {
  return std::make_unique<ColorBlocks>();
}

}  // namespace clothlab::builtin
