// How many threads a plugin's own parallel loops run on, for every plugin that threads: its
// `threads` parameter (threads_param) when set, else the host's count (clothlab.threads/1:
// the CLI's --threads, a game's share of the cores), else OpenMP's default. Include it after
// sdk.hpp; it uses OpenMP when the plugin is built with it and one thread when not.
#pragma once

#include <clothlab/plugin.h>

#include <algorithm>
#include <clothlab/sdk.hpp>
#include <cstdint>
#include <optional>

#ifdef _OPENMP
#include <omp.h>
#endif

namespace clothlab::sdk {

// The parameter that overrides the host's count; 0, the default, keeps to it.
constexpr clothlab_param_spec threads_param() {
  return int_param("threads", 0, 0, 256,
                   "threads for the parallel sweeps; 0 = the host's count (clothlab.threads/1, "
                   "the CLI's --threads)");
}

// The count from the parameter's value, the host's offer and the runtime's default; 1 when
// the work is too small to be worth a team.
constexpr int resolve_threads(long requested, std::optional<uint32_t> host, int runtime_default,
                              bool worth_splitting) {
  if (!worth_splitting) return 1;
  if (requested > 0) return static_cast<int>(requested);
  if (host) return static_cast<int>(std::max<uint32_t>(*host, 1));
  return std::max(runtime_default, 1);
}

// The count for this system's work; call from `prepare`.
template <class Real>
int plugin_threads(const System<Real>& system, long requested, bool worth_splitting) {
#ifdef _OPENMP
  const int runtime_default = omp_get_max_threads();
#else
  const int runtime_default = 1;
#endif
  return resolve_threads(requested, system.threads(), runtime_default, worth_splitting);
}

// Builds the OpenMP team of `threads` (the first parallel region of a size allocates), so that
// `step` does not: call from `prepare` with plugin_threads' count.
inline void start_thread_team([[maybe_unused]] int threads) {
#ifdef _OPENMP
  if (threads > 1) {
#pragma omp parallel num_threads(threads)
    { (void)omp_get_thread_num(); }
  }
#endif
}

}  // namespace clothlab::sdk
