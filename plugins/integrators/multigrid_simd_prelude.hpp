// The multigrid set-up's prelude for its Galerkin products' per-target copies (CMakeLists.txt):
// the types the copies share with the rest of the plugin, then the target's instruction sets
// (the core's simd_target_begin.hpp).
#pragma once

#include "multigrid_block_table.hpp"
#include "multigrid_level.hpp"
#include "multigrid_transfer.hpp"

// Last: what follows is compiled for the target.
#include "simd_target_begin.hpp"
