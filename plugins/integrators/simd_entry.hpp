// Which copy of a plugin module compiled per SIMD target runs here (clothlab_add_simd_copies,
// plugins/integrators/CMakeLists.txt): the plugin's own (its build's flags) or, in a portable
// build, a wider target's, chosen as the core chooses its engine's
// (clothlab/sdk/simd_target.hpp): the widest the CPU runs, or the one CLOTHLAB_SIMD names.
#pragma once

#include <clothlab/plugin.h>

#include <clothlab/sdk/error.hpp>
#include <clothlab/sdk/simd_target.hpp>

namespace clothlab::builtin {

// A module's entry for a wider target, or nullptr where the build lacks the target (its
// declaration too).
#if defined(CLOTHLAB_SIMD_WITH_AVX2)
#define CLOTHLAB_AVX2_ENTRY(entry) (entry)
#else
#define CLOTHLAB_AVX2_ENTRY(entry) nullptr
#endif
#if defined(CLOTHLAB_SIMD_WITH_AVX512)
#define CLOTHLAB_AVX512_ENTRY(entry) (entry)
#else
#define CLOTHLAB_AVX512_ENTRY(entry) nullptr
#endif

// The entry of the target that runs here. Throws sdk::Error (invalid argument) with the
// choice's one-line reason when CLOTHLAB_SIMD names a target that cannot run here.
template <class Entry>
Entry simd_entry(Entry own, Entry avx2, Entry avx512) {
  const sdk::SimdChoice choice = sdk::choose_simd_target(sdk::kBuiltSimdTargets);
  if (choice.target.empty()) throw sdk::Error(CLOTHLAB_ERROR_INVALID_ARGUMENT, choice.error);
  if (choice.target == "avx512" && avx512 != nullptr) return avx512;
  if (choice.target == "avx2" && avx2 != nullptr) return avx2;
  return own;
}

}  // namespace clothlab::builtin
