// The SIMD targets of the core's engine (docs/reference/simd-dispatch.md).
#pragma once

#include <span>
#include <string_view>

namespace clothlab {

// The SIMD target a Cloth made now runs its kernels on: the widest this build contains that the
// CPU runs, or the one the environment variable CLOTHLAB_SIMD names (sdk/simd_target.hpp).
// Throws std::invalid_argument, one line naming the variable, the CPU's features and the targets
// built, when the variable names a target that cannot run here; so does a Cloth's constructor.
std::string_view simd_target();

// The targets this build's core contains, narrowest first: `native`, or `portable`, `avx2` and
// `avx512`.
std::span<const std::string_view> simd_targets_built();

}  // namespace clothlab
