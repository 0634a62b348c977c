// The start of a translation unit's per-target part, for a module that compiles its kernels
// once per SIMD target (docs/reference/simd-dispatch.md). CMake includes the module's prelude
// first (-include), which includes every header that is not compiled per target and then this
// one: the standard headers below, then the target's instruction sets for the rest of the unit
// (#pragma GCC target). What follows must lie in CLOTHLAB_SIMD_NAMESPACE (simd_namespace.hpp);
// what came before keeps the build's flags, so an inline function of the standard library
// compiled here is the same code as everywhere else and the linker may merge it safely.
#pragma once

#include <immintrin.h>
#include <omp.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cfloat>
#include <charconv>
#include <chrono>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <limits>
#include <memory>
#include <new>
#include <numeric>
#include <optional>
#include <span>
#include <sstream>
#include <stdexcept>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>
#include <vector>

#include "simd_namespace.hpp"

#if defined(CLOTHLAB_SIMD_AVX512)
#pragma GCC push_options
#pragma GCC target( \
    "sse4.2,popcnt,avx,avx2,fma,bmi,bmi2,lzcnt,f16c,movbe,avx512f,avx512bw,avx512dq,avx512vl,avx512cd")
#elif defined(CLOTHLAB_SIMD_AVX2)
#pragma GCC push_options
#pragma GCC target("sse4.2,popcnt,avx,avx2,fma,bmi,bmi2,lzcnt,f16c,movbe")
#endif
