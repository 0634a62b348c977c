// Stage vectors of a multi-stage method are written by lincomb on active particles only,
// but the force evaluation also reads the pinned particles' entries (springs to the pins,
// damping relative to them). This copies just those entries — the gaps between the active
// ranges, usually a handful of particles — instead of whole vectors.
#pragma once

#include <clothlab/sdk.hpp>
#include <cstdint>

namespace clothlab::builtin {

template <class Real>
void copy_pinned(const sdk::System<Real>& system, Real* dst, const Real* src) {
  const uint32_t stride = system.stride();
  const auto copy_particles = [&](uint32_t begin, uint32_t end) {
    for (uint32_t k = 0; k < 3; ++k)
      for (uint32_t i = begin; i < end; ++i) dst[k * stride + i] = src[k * stride + i];
  };
  uint32_t next = 0;
  for (const clothlab_range& range : system.active()) {
    copy_particles(next, range.begin);
    next = range.end;
  }
  copy_particles(next, system.particle_count());
}

}  // namespace clothlab::builtin
