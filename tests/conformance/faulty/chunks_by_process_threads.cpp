// Faulty: removes the free particles' mean velocity drift each step with its own chunked sum,
// one chunk per thread of the process (read from /proc/self/status in prepare). The host's
// thread team makes that count 2 with 2 engine threads and 1 with one, the summation order
// changes and so do the bits; numerics.threads-* catch it. (The host's reductions extension
// gives sums independent of the thread count; this plugin does not use it.)
#include <algorithm>
#include <fstream>
#include <string>

#include "symplectic_euler.hpp"

struct ChunksByProcessThreads : clothlab::faulty::SymplecticEulerBase {
  using SymplecticEulerBase::SymplecticEulerBase;
  static constexpr const char* id = "chunks-by-process-threads";
  static constexpr const char* name = "Symplectic Euler with a thread-count-chunked sum";
  static constexpr const char* description =
      "faulty: a sum's chunk count is the process's thread count";

  static uint32_t process_threads() {
    std::ifstream status("/proc/self/status");
    for (std::string line; std::getline(status, line);)
      if (line.rfind("Threads:", 0) == 0) return std::max(1, std::stoi(line.substr(8)));
    return 1;
  }

  template <class Real>
  void prepare(clothlab::sdk::System<Real>& system) {
    SymplecticEulerBase::prepare(system);
    chunks_ = process_threads();
  }

  template <class Real>
  void step(clothlab::sdk::System<Real>& system, double t, double dt) {
    SymplecticEulerBase::step(system, t, dt);
    const uint32_t n = system.particle_count(), stride = system.stride();
    const Real* inverse_mass = system.inverse_mass();
    Real* v = system.v();
    for (uint32_t k = 0; k < 3; ++k) {
      Real total = 0;
      uint32_t free = 0;
      for (uint32_t chunk = 0; chunk < chunks_; ++chunk) {
        Real partial = 0;
        for (uint32_t i = chunk * n / chunks_; i < (chunk + 1) * n / chunks_; ++i)
          if (inverse_mass[i] != Real(0)) {
            partial += v[k * stride + i];
            ++free;
          }
        total += partial;
      }
      const Real mean = free ? total / Real(free) : Real(0);
      for (uint32_t i = 0; i < n; ++i)
        if (inverse_mass[i] != Real(0)) v[k * stride + i] -= mean;
    }
  }

  uint32_t chunks_ = 1;
};

CLOTHLAB_PLUGIN_ENTRY("faulty-chunks-by-process-threads", "0.0.1",
                      clothlab::sdk::integrators<ChunksByProcessThreads>,
                      clothlab::sdk::scenarios<>)
