// xpbd's prelude for its grid sweep's and lane blocks' per-target copies (CMakeLists.txt): the
// types the copies share with the rest of the plugin, then the target's instruction sets (the
// core's simd_target_begin.hpp).
#pragma once

#include "xpbd_color_row.hpp"
#include "xpbd_constraint.hpp"
#include "xpbd_grid_plan.hpp"
#include "xpbd_lane_blocks.hpp"
#include "xpbd_substep.hpp"

// Last: what follows is compiled for the target.
#include "simd_target_begin.hpp"
