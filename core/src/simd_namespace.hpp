// The namespace of a module's code that is compiled once per SIMD target (simd_target_begin.hpp):
// each copy's inline functions and templates get names of their own, so the linker never
// merges an AVX-512 copy into a caller that the CPU runs on AVX2. A translation unit compiled
// with the build's own flags names its copy `baseline`.
#pragma once

#if !defined(CLOTHLAB_SIMD_NAMESPACE)
#define CLOTHLAB_SIMD_NAMESPACE baseline
#endif

// name_<target>: a per-target entry point's name, outside the target's namespace.
#define CLOTHLAB_SIMD_ENTRY(name) CLOTHLAB_SIMD_ENTRY_PASTE(name, CLOTHLAB_SIMD_NAMESPACE)
#define CLOTHLAB_SIMD_ENTRY_PASTE(name, target) CLOTHLAB_SIMD_ENTRY_PASTE2(name, target)
#define CLOTHLAB_SIMD_ENTRY_PASTE2(name, target) name##_##target
