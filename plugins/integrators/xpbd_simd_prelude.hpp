// xpbd's prelude for its row kernel's per-target copies (CMakeLists.txt): the type the copies
// share, then the target's instruction sets (the core's simd_target_begin.hpp).
#pragma once

#include "xpbd_color_row.hpp"

// Last: what follows is compiled for the target.
#include "simd_target_begin.hpp"
