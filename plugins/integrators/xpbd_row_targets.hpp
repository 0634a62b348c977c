// The float row kernel of the SIMD target that runs here: the plugin's own copy (its build's
// flags) or, in a portable build, a wider target's (xpbd_row_kernel_target.cpp), chosen as the
// core chooses its engine's (clothlab/sdk/simd_target.hpp): the widest the CPU runs, or the one
// CLOTHLAB_SIMD names.
#pragma once

#include <clothlab/plugin.h>

#include <clothlab/sdk.hpp>
#include <clothlab/sdk/error.hpp>
#include <clothlab/sdk/simd_target.hpp>
#include <string_view>

#include "xpbd_color_row.hpp"
#include "xpbd_row_kernel.hpp"

namespace clothlab::builtin {

using FloatRowKernel = void (*)(const ColorRow<float>&);

#if defined(CLOTHLAB_SIMD_WITH_AVX2)
void project_float_row_avx2(const ColorRow<float>& row);
#endif
#if defined(CLOTHLAB_SIMD_WITH_AVX512)
void project_float_row_avx512(const ColorRow<float>& row);
#endif

// Throws sdk::Error (invalid argument) with the choice's one-line reason when CLOTHLAB_SIMD
// names a target that cannot run here.
inline FloatRowKernel choose_float_row_kernel() {
  const sdk::SimdChoice choice = sdk::choose_simd_target(sdk::kBuiltSimdTargets);
  if (choice.target.empty()) throw sdk::Error(CLOTHLAB_ERROR_INVALID_ARGUMENT, choice.error);
#if defined(CLOTHLAB_SIMD_WITH_AVX512)
  if (choice.target == "avx512") return project_float_row_avx512;
#endif
#if defined(CLOTHLAB_SIMD_WITH_AVX2)
  if (choice.target == "avx2") return project_float_row_avx2;
#endif
  return project_row<float>;
}

}  // namespace clothlab::builtin
