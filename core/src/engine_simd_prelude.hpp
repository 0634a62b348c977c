// The core's prelude for the engine's per-target copies (core/CMakeLists.txt): the headers the
// engine shares with the rest of the core, compiled with the build's flags, then the target's
// instruction sets (simd_target_begin.hpp).
#pragma once

#include <clothlab/ext/attachment_targets.h>
#include <clothlab/ext/cg_step.h>
#include <clothlab/ext/contacts.h>
#include <clothlab/ext/definite_jacobian.h>
#include <clothlab/ext/external_forces.h>
#include <clothlab/ext/grid.h>
#include <clothlab/ext/jacobian.h>
#include <clothlab/ext/reductions.h>
#include <clothlab/ext/threads.h>
#include <clothlab/plugin.h>
#include <omp.h>

#include <clothlab/core/attachment_path.hpp>
#include <clothlab/core/cloth.hpp>
#include <clothlab/core/cloth_model.hpp>
#include <clothlab/core/collider.hpp>
#include <clothlab/core/contact.hpp>
#include <clothlab/core/team_governor.hpp>

#include "aligned_buffer.hpp"
#include "engine.hpp"
#include "engine_state.hpp"
#include "grid.hpp"
#include "grid_colors.hpp"
#include "rkn_step.hpp"
#include "scratch_layout.hpp"

// Last: what follows is compiled for the target.
#include "simd_target_begin.hpp"
