#include "spring_list_forces.hpp"

#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <numeric>
#include <tuple>
#include <type_traits>

#include "air_kernel.hpp"
#include "simd_namespace.hpp"
#include "spring_kernel.hpp"
#include "wind_kernel.hpp"

namespace clothlab::detail::inline CLOTHLAB_SIMD_NAMESPACE {
namespace {

constexpr std::size_t kChunk = 1024;  // items per thread work item

std::size_t chunks_of(std::size_t items) { return (items + kChunk - 1) / kChunk; }

}  // namespace

template <class Real>
SpringListForces<Real>::SpringListForces(const ClothModel& model, const Scene& scene,
                                         std::size_t stride, const Real* inverse_mass,
                                         bool velocity_forces, int threads, bool parallel)
    : n_(model.particle_count),
      stride_(stride),
      inverse_mass_(inverse_mass),
      threads_(threads),
      parallel_(parallel),
      velocity_forces_(velocity_forces),
      springs_(model, velocity_forces),
      spring_count_(model.spring_count()),
      triangles_(model.triangles) {
  spring_force_ = AlignedBuffer<Real>(3 * springs_.slots());

  for (int k = 0; k < 3; ++k) {
    gravity_[k] = static_cast<Real>(scene.gravity[k]);
    wind_direction_[k] = static_cast<Real>(scene.wind_direction[k]);
    air_wind_[k] = static_cast<Real>(scene.air.wind_velocity[k]);
  }
  const std::size_t triangles = model.triangle_count();
  wind_ = scene.has_wind() && triangles > 0;
  air_ = scene.has_air() && triangles > 0;
  wind_strength_ = static_cast<Real>(scene.wind_strength);
  wind_pressure(wind_direction_, wind_strength_, kScalarInverseSqrtScale, wind_pressure_);
  air_drag_twelfth_ = static_cast<Real>(scene.air.density * scene.air.drag_coefficient / 12.0);
  air_lift_twelfth_ = static_cast<Real>(scene.air.density * scene.air.lift_coefficient / 12.0);
  if (wind_ || air_) {
    order_triangles();
    triangle_share_ = AlignedBuffer<Real>(3 * triangles);
    triangle_offsets_.assign(n_ + 1, 0);
    for (uint32_t corner : triangles_) ++triangle_offsets_[corner + 1];
    for (std::size_t i = 0; i < n_; ++i) triangle_offsets_[i + 1] += triangle_offsets_[i];
    adjacent_triangles_.resize(triangle_offsets_[n_]);
    std::vector<uint32_t> next(triangle_offsets_.begin(), triangle_offsets_.end() - 1);
    for (std::size_t t = 0; t < triangles; ++t)
      for (int corner = 0; corner < 3; ++corner)
        adjacent_triangles_[next[triangles_[3 * t + corner]]++] = static_cast<uint32_t>(t);
  }
  formed_x_ = AlignedBuffer<Real>(3 * stride_);
  formed_v_ = AlignedBuffer<Real>(3 * stride_);
}

template <class Real>
void SpringListForces<Real>::order_triangles() {
  const std::size_t triangles = triangles_.size() / 3;
  std::vector<uint32_t> rotated(triangles_.size());
  for (std::size_t t = 0; t < triangles; ++t) {
    const uint32_t* corners = &triangles_[3 * t];
    const std::size_t low = std::min_element(corners, corners + 3) - corners;
    for (std::size_t c = 0; c < 3; ++c) rotated[3 * t + c] = corners[(low + c) % 3];
  }
  std::vector<uint32_t> order(triangles);
  std::iota(order.begin(), order.end(), 0u);
  const auto key = [&](uint32_t t) {
    const uint32_t* c = &rotated[3 * t];
    return std::tuple{c[1] - c[0], c[2] - c[0], c[0]};
  };
  std::sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) { return key(a) < key(b); });
  const auto follows = [&](std::size_t i) {  // order[i, i + kSpringBlock) advance by one
    for (std::size_t l = 1; l < kSpringBlock; ++l)
      for (std::size_t c = 0; c < 3; ++c)
        if (rotated[3 * order[i + l] + c] != rotated[3 * order[i] + c] + l) return false;
    return true;
  };
  std::vector<uint32_t> runs, rest;
  for (std::size_t i = 0; i < triangles;) {
    if (i + kSpringBlock <= triangles && follows(i)) {
      runs.insert(runs.end(), order.begin() + static_cast<std::ptrdiff_t>(i),
                  order.begin() + static_cast<std::ptrdiff_t>(i + kSpringBlock));
      i += kSpringBlock;
    } else {
      rest.push_back(order[i++]);
    }
  }
  std::sort(rest.begin(), rest.end());  // the others keep the model's order and corners
  const std::vector<uint32_t> model = triangles_;
  for (std::size_t t = 0; t < runs.size(); ++t)
    for (std::size_t c = 0; c < 3; ++c) triangles_[3 * t + c] = rotated[3 * runs[t] + c];
  for (std::size_t t = 0; t < rest.size(); ++t)
    for (std::size_t c = 0; c < 3; ++c)
      triangles_[3 * (runs.size() + t) + c] = model[3 * rest[t] + c];
  lane_triangles_ = runs.size();
}

template <class Real>
const Real* SpringListForces<Real>::form(const StateCombination<Real>& state, Real* out) {
  if (state.count == 0) return state.base;
  const auto chunks = static_cast<std::ptrdiff_t>(chunks_of(n_));
#pragma omp parallel for schedule(static) num_threads(threads_) if (parallel_)
  for (std::ptrdiff_t chunk = 0; chunk < chunks; ++chunk) {
    const std::size_t begin = static_cast<std::size_t>(chunk) * kChunk;
    const std::size_t count = std::min(kChunk, n_ - begin);
    for (std::size_t k = 0; k < 3; ++k) {
      const std::size_t at = k * stride_ + begin;
      const Real* vectors[StateCombination<Real>::kMaxTerms];
      for (uint32_t t = 0; t < state.count; ++t) vectors[t] = state.vectors[t] + at;
      combine_row(out + at, state.base + at, state.count, state.coefficients, vectors,
                  inverse_mass_ + begin, count);
    }
  }
  return out;
}

template <class Real>
Real SpringListForces<Real>::spring_sweep(const Real* x, const Real* v, Real* a, bool triangles) {
  Real check = 0;
  const std::size_t tile = kChunk / kSpringBlock;
  springs_.sweep(
      tile, threads_, parallel_,
      [&](std::size_t begin, std::size_t end) {
        springs_.forces(x, v, stride_, begin, end, spring_force_.data());
      },
      [&](std::size_t, std::size_t begin, std::size_t end) {
        Real tile_check = 0;
        for (std::size_t block = begin; block < end; ++block)
          tile_check += gather_block(block, a, true, triangles);
#pragma omp atomic
        check += tile_check;
      });
  return check;
}

template <class Real>
void SpringListForces<Real>::triangle_pass(const Real* x, const Real* v) {
  const std::size_t triangles = triangles_.size() / 3;
  const auto chunks = static_cast<std::ptrdiff_t>(chunks_of(triangles));
#pragma omp parallel for schedule(static) num_threads(threads_) if (parallel_)
  for (std::ptrdiff_t chunk = 0; chunk < chunks; ++chunk) {
    std::size_t begin = static_cast<std::size_t>(chunk) * kChunk;
    const std::size_t end = std::min(triangles, begin + kChunk);
#if defined(CLOTHLAB_FLOAT_LANES)
    if constexpr (std::is_same_v<Real, float>) {
      // The blocks of triangles whose corners follow in order: the wind on lanes, plain loads.
      if (!air_)
        for (; begin < std::min(end, lane_triangles_); begin += kSpringBlock)
          wind_block_lanes(x, begin);
    }
#endif
    triangle_shares(x, v, begin, end);
  }
}

template <class Real>
void SpringListForces<Real>::triangle_shares(const Real* x, const Real* v, std::size_t begin,
                                             std::size_t end) {
  const std::size_t s1 = stride_, s2 = 2 * stride_;
  const Real third = Real(1) / Real(3);
  for (std::size_t t = begin; t < end; ++t) {
    const std::size_t a = triangles_[3 * t], b = triangles_[3 * t + 1], c = triangles_[3 * t + 2];
    const Real e1[3] = {x[b] - x[a], x[b + s1] - x[a + s1], x[b + s2] - x[a + s2]};
    const Real e2[3] = {x[c] - x[a], x[c + s1] - x[a + s1], x[c + s2] - x[a + s2]};
    Real share[3] = {0, 0, 0};
    if (wind_) triangle_wind_share(e1, e2, wind_pressure_, share);
    if (air_) {
      Real velocity[3] = {0, 0, 0};
      if (v != nullptr)
        for (std::size_t k = 0; k < 3; ++k) {
          const std::size_t at = k * stride_;
          velocity[k] = (v[a + at] + v[b + at] + v[c + at]) * third;
        }
      Real air[3];
      triangle_air_share(e1, e2, velocity, air_wind_, air_drag_twelfth_, air_lift_twelfth_, air);
      for (int k = 0; k < 3; ++k) share[k] += air[k];
    }
    for (int k = 0; k < 3; ++k) triangle_share_[3 * t + k] = share[k];
  }
}

#if defined(CLOTHLAB_FLOAT_LANES)
template <class Real>
void SpringListForces<Real>::wind_block_lanes(const Real* x, std::size_t t) {
  if constexpr (std::is_same_v<Real, float>) {
    const uint32_t a = triangles_[3 * t], b = triangles_[3 * t + 1], c = triangles_[3 * t + 2];
    float lane_pressure[3];
    wind_pressure(wind_direction_, wind_strength_, kLanesInverseSqrtScale, lane_pressure);
    Floats e1[3], e2[3], pressure[3], share[3];
    for (std::size_t k = 0; k < 3; ++k) {
      const float* component = x + k * stride_;
      const Floats corner = load_floats(component + a);
      e1[k] = load_floats(component + b) - corner;
      e2[k] = load_floats(component + c) - corner;
      pressure[k] = broadcast(lane_pressure[k]);
    }
    triangle_wind_share(e1, e2, pressure, share);
    alignas(kAlignment) float lanes[3][kSpringBlock];
    for (std::size_t k = 0; k < 3; ++k) store_floats(lanes[k], share[k]);
    for (std::size_t l = 0; l < kSpringBlock; ++l)
      for (std::size_t k = 0; k < 3; ++k) triangle_share_[3 * (t + l) + k] = lanes[k][l];
  }
}
#endif

template <class Real>
Real SpringListForces<Real>::gather_block(std::size_t block, Real* a, bool springs,
                                          bool triangles) const {
  alignas(kAlignment) Real force[3][kSpringBlock] = {};
  if (springs) springs_.sum_incident(spring_force_.data(), block, force);
  const std::size_t first = block * kSpringBlock;
  const std::size_t count = std::min(kSpringBlock, n_ - first);
  if (triangles)
    for (std::size_t l = 0; l < count; ++l)
      for (uint32_t e = triangle_offsets_[first + l]; e < triangle_offsets_[first + l + 1]; ++e)
        for (std::size_t k = 0; k < 3; ++k)
          force[k][l] += triangle_share_[3 * adjacent_triangles_[e] + k];
#if defined(CLOTHLAB_FLOAT_LANES)
  if constexpr (std::is_same_v<Real, float>) {
    if (count == kSpringBlock) {
      const Floats inverse_mass = load_floats(inverse_mass_ + first);
      const LaneMask active = greater(inverse_mass, zero_floats());
      Floats check = zero_floats();
      for (std::size_t k = 0; k < 3; ++k) {
        const Floats value = keep(active, fused_multiply_add(load_floats(force[k]), inverse_mass,
                                                             broadcast(gravity_[k])));
        store_floats(a + k * stride_ + first, value);
        check = check + zero_floats() * value;
      }
      return no_lane(unordered(check, check)) ? 0.0f : std::numeric_limits<float>::quiet_NaN();
    }
  }
#endif
  Real check = 0;
  for (std::size_t k = 0; k < 3; ++k)
    for (std::size_t l = 0; l < count; ++l) {
      const Real inverse_mass = inverse_mass_[first + l];
      const Real value =
          inverse_mass > Real(0) ? force[k][l] * inverse_mass + gravity_[k] : Real(0);
      a[k * stride_ + first + l] = value;
      check += Real(0) * value;
    }
  return check;
}

template <class Real>
Real SpringListForces<Real>::gather_external(Real* a, bool triangles) {
  const std::size_t blocks = springs_.particle_blocks();
  const auto chunks = static_cast<std::ptrdiff_t>(chunks_of(blocks * kSpringBlock));
  Real check = 0;
#pragma omp parallel for schedule(static) num_threads(threads_) if (parallel_) reduction(+ : check)
  for (std::ptrdiff_t chunk = 0; chunk < chunks; ++chunk) {
    const std::size_t begin = static_cast<std::size_t>(chunk) * (kChunk / kSpringBlock);
    const std::size_t end = std::min(blocks, begin + kChunk / kSpringBlock);
    for (std::size_t block = begin; block < end; ++block)
      check += gather_block(block, a, false, triangles);
  }
  return check;
}

template <class Real>
bool SpringListForces<Real>::evaluate(const StateCombination<Real>& x,
                                      const StateCombination<Real>* v, Real* a,
                                      StageCounters& counters) {
  using Clock = std::chrono::steady_clock;
  const auto start = Clock::now();
  const Real* positions = form(x, formed_x_.data());
  const Real* velocities = v == nullptr ? nullptr : form(*v, formed_v_.data());
  const auto formed = Clock::now();
  const bool cells = wind_ || air_;
  if (cells) triangle_pass(positions, velocities);
  const auto triangles_done = Clock::now();
  // The sums, which also add the triangles' shares, count with the springs.
  const Real check = spring_sweep(positions, velocities, a, cells);
  const double external = std::chrono::duration<double>(triangles_done - formed).count();
  counters.external_forces_s += external;
  counters.internal_forces_s +=
      std::chrono::duration<double>(Clock::now() - start).count() - external;
  ++counters.force_evals;
  counters.springs_evaluated += spring_count_;
  counters.springs_damped += velocities != nullptr ? springs_.damped_count() : 0;
  counters.normals_computed += cells ? triangles_.size() / 3 : 0;
  return check == Real(0);
}

template <class Real>
bool SpringListForces<Real>::evaluate_external(const Real* x, const Real* v, Real* a) {
  const bool cells = wind_ || air_;
  if (cells) triangle_pass(x, v);
  return gather_external(a, cells) == Real(0);
}

template <class Real>
void SpringListForces<Real>::reserve_stages(uint32_t stages) {
  while (stage_a_.size() < stages) stage_a_.emplace_back(3 * stride_);
  reserved_stages_ = std::max(reserved_stages_, stages);
}

template <class Real>
bool SpringListForces<Real>::step_rkn(Real* x, Real* v, const RknStep<Real>& step,
                                      StageCounters& counters) {
  bool finite = true;
  for (uint32_t s = 0; s < step.stages; ++s) {
    // X_s = x + x_velocity[s] v + sum_k x_stage[s][k] A_k, V_s = v + sum_k v_stage[s][k] A_k.
    StateCombination<Real> stage_x, stage_v;
    stage_x.base = x;
    stage_x.vectors[0] = v;
    stage_x.coefficients[0] = step.x_velocity[s];
    stage_x.count = 1 + s;
    stage_v.base = v;
    stage_v.count = s;
    for (uint32_t k = 0; k < s; ++k) {
      stage_x.vectors[1 + k] = stage_a_[k].data();
      stage_x.coefficients[1 + k] = step.x_stage[s][k];
      stage_v.vectors[k] = stage_a_[k].data();
      stage_v.coefficients[k] = step.v_stage[s][k];
    }
    finite = evaluate(stage_x, &stage_v, stage_a_[s].data(), counters) && finite;
  }
  // x += h v + sum_k x_weights[k] A_k, v += sum_k v_weights[k] A_k on the active particles.
  const auto chunks = static_cast<std::ptrdiff_t>(chunks_of(n_));
#pragma omp parallel for schedule(static) num_threads(threads_) if (parallel_)
  for (std::ptrdiff_t chunk = 0; chunk < chunks; ++chunk) {
    const std::size_t begin = static_cast<std::size_t>(chunk) * kChunk;
    const std::size_t end = std::min(n_, begin + kChunk);
    for (std::size_t k = 0; k < 3; ++k)
      for (std::size_t i = begin; i < end; ++i) {
        if (inverse_mass_[i] == Real(0)) continue;
        const std::size_t at = k * stride_ + i;
        Real dx = step.h * v[at], dv = 0;
        for (uint32_t s = 0; s < step.stages; ++s) {
          dx += step.x_weights[s] * stage_a_[s][at];
          dv += step.v_weights[s] * stage_a_[s][at];
        }
        x[at] += dx;
        v[at] += dv;
      }
  }
  return finite;
}

template class SpringListForces<float>;
template class SpringListForces<double>;

}  // namespace clothlab::detail::inline CLOTHLAB_SIMD_NAMESPACE
