// Which of a module's SIMD targets runs on this CPU: the widest the module was built for and the
// CPU supports, or the one the environment variable CLOTHLAB_SIMD names. A module (the core, a
// plugin) compiles its kernels once per target (docs/reference/simd-dispatch.md) and asks
// choose_simd_target once, with the names of the targets it contains, narrowest first.
//
// Targets: `portable` (x86-64's baseline, SSE2), `avx2` (x86-64-v3: AVX2 and FMA), `avx512`
// (x86-64-v4: AVX-512 F, BW, DQ and VL), and `native`, what a -march=native build compiles for:
// its own machine, so a native build contains no other target.
#pragma once

#include <cstdlib>
#include <span>
#include <string>
#include <string_view>

namespace clothlab::sdk {

struct SimdChoice {
  std::string_view target;  // empty when `error` says why none
  std::string error;        // one line naming the variable, the CPU's features and the targets
};

inline constexpr std::string_view kSimdVariable = "CLOTHLAB_SIMD";

// Whether this CPU runs code compiled for `target` (a name above; false for any other).
inline bool cpu_runs_simd_target(std::string_view target) {
  if (target == "portable" || target == "native") return true;
#if defined(__x86_64__) || defined(__i386__)
  __builtin_cpu_init();
  const bool avx2 = __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
  if (target == "avx2") return avx2;
  if (target == "avx512")
    return avx2 && __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512bw") &&
           __builtin_cpu_supports("avx512dq") && __builtin_cpu_supports("avx512vl");
#endif
  return false;
}

// The CPU's features that decide between the targets, as `lscpu` names them.
inline std::string cpu_simd_features() {
  std::string features;
#if defined(__x86_64__) || defined(__i386__)
  __builtin_cpu_init();
  const auto add = [&features](bool present, const char* name) {
    if (!present) return;
    if (!features.empty()) features += ' ';
    features += name;
  };
  add(__builtin_cpu_supports("sse4.2"), "sse4_2");
  add(__builtin_cpu_supports("avx"), "avx");
  add(__builtin_cpu_supports("avx2"), "avx2");
  add(__builtin_cpu_supports("fma"), "fma");
  add(__builtin_cpu_supports("avx512f"), "avx512f");
  add(__builtin_cpu_supports("avx512bw"), "avx512bw");
  add(__builtin_cpu_supports("avx512dq"), "avx512dq");
  add(__builtin_cpu_supports("avx512vl"), "avx512vl");
#endif
  return features.empty() ? std::string("none of sse4_2 avx avx2 fma avx512*") : features;
}

// `built`: the module's targets, narrowest first. `forced`: the variable's value (nullptr or
// empty: not set), read from the environment unless given.
inline SimdChoice choose_simd_target(std::span<const std::string_view> built, const char* forced) {
  std::string built_names;
  for (std::string_view name : built) {
    if (!built_names.empty()) built_names += ", ";
    built_names += name;
  }
  const auto refuse = [&](std::string_view value, std::string_view why) {
    return SimdChoice{{},
                      std::string(kSimdVariable) + "=" + std::string(value) + ": " +
                          std::string(why) + " (this CPU has: " + cpu_simd_features() +
                          "; targets built: " + built_names + ")"};
  };
  if (forced == nullptr || *forced == '\0') {
    std::string_view widest;
    for (std::string_view name : built)
      if (cpu_runs_simd_target(name)) widest = name;
    if (widest.empty()) return refuse("(unset)", "no target built runs on this CPU");
    return {widest, {}};
  }
  const std::string_view value(forced);
  for (std::string_view name : built) {
    if (name != value) continue;
    if (!cpu_runs_simd_target(name)) return refuse(value, "this CPU lacks the target");
    return {name, {}};
  }
  const bool known =
      value == "portable" || value == "avx2" || value == "avx512" || value == "native";
  return refuse(value, known ? "target not built into this build"
                             : "unknown target; allowed: portable, avx2, avx512, native");
}

inline SimdChoice choose_simd_target(std::span<const std::string_view> built) {
  return choose_simd_target(built, std::getenv(std::string(kSimdVariable).c_str()));
}

#if defined(CLOTHLAB_SIMD_BASELINE)
// The targets the module including this was built with, narrowest first, from the definitions
// its build sets (CLOTHLAB_SIMD_BASELINE, CLOTHLAB_SIMD_WITH_AVX2, CLOTHLAB_SIMD_WITH_AVX512).
// Internal linkage: the core and a plugin each keep their own list.
static constexpr std::string_view kBuiltSimdTargets[] = {
    CLOTHLAB_SIMD_BASELINE,
#if defined(CLOTHLAB_SIMD_WITH_AVX2)
    "avx2",
#endif
#if defined(CLOTHLAB_SIMD_WITH_AVX512)
    "avx512",
#endif
};
#endif

}  // namespace clothlab::sdk
