// SpringJacobian's products on the spring list (spring_jacobian.hpp): the path of any mesh, and
// of a grid forced onto the general path. Two passes, as the spring-list forces, on the slots of
// SpringLanes (spring_lanes.hpp): each spring's M (u_j - u_i) once into its own slot, then per
// particle the sum of its slots in one fixed order. No thread writes another's particles, so the
// result is the same bits on any thread count. The CG products run on lanes, tile by tile
// (SpringLanes::sweep), from each slot's 1/l, fixed by linearise (definite_products); the other
// products build M per spring as the block forms do (spring_block).
#include <omp.h>

#include <algorithm>
#include <type_traits>

#include "simd_namespace.hpp"
#include "spring_jacobian.hpp"

namespace clothlab::detail::inline CLOTHLAB_SIMD_NAMESPACE {
namespace {

constexpr std::size_t kChunk = 2048;  // slots or particles per thread work item

std::ptrdiff_t chunks_of(std::size_t items) {
  return static_cast<std::ptrdiff_t>((items + kChunk - 1) / kChunk);
}

constexpr std::size_t kChunkBlocks = kChunk / kSpringBlock;

}  // namespace

template <class Real>
template <class Block>
void SpringJacobian<Real>::list_spring_products(const Real* u, Block&& block) const {
  const SpringLanes<Real>& lanes = *spring_lanes_;
  const std::size_t slots = lanes.slots();
  const uint32_t dead = static_cast<uint32_t>(topology_.spring_count());
  const uint32_t* first = topology_.first.data();
  const uint32_t* second = topology_.second.data();
  Real* products = spring_products_.data();
#pragma omp parallel for schedule(static) num_threads(threads_) if (parallel_)
  for (std::ptrdiff_t chunk = 0; chunk < chunks_of(slots); ++chunk) {
    const std::size_t begin = static_cast<std::size_t>(chunk) * kChunk;
    const std::size_t end = std::min(slots, begin + kChunk);
    for (std::size_t s = begin; s < end; ++s) {
      const uint32_t spring = lanes.spring_in(s);
      if (spring == dead) {
        for (std::size_t r = 0; r < 3; ++r) products[r * slots + s] = Real(0);
        continue;
      }
      const std::size_t i = first[spring], j = second[spring];
      const bool i_active = inverse_mass_[i] > Real(0), j_active = inverse_mass_[j] > Real(0);
      Real du[3];
      for (std::size_t k = 0; k < 3; ++k)
        du[k] =
            (j_active ? u[k * stride_ + j] : Real(0)) - (i_active ? u[k * stride_ + i] : Real(0));
      Real m[9];
      block(spring, m);
      for (std::size_t r = 0; r < 3; ++r)
        products[r * slots + s] = m[3 * r] * du[0] + m[3 * r + 1] * du[1] + m[3 * r + 2] * du[2];
    }
  }
}

template <class Real>
template <bool Shifted>
double SpringJacobian<Real>::list_gather_blocks(const Real* u, Real* out, const Real* ring,
                                                std::size_t begin, std::size_t end) const {
  const SpringLanes<Real>& lanes = *spring_lanes_;
  double dot = 0.0;
#if defined(CLOTHLAB_FLOAT_LANES)
  Doubles dots[2] = {zero_doubles(), zero_doubles()};
#endif
  for (std::size_t block = begin; block < end; ++block) {
    alignas(kAlignment) Real sum[3][kSpringBlock];
    lanes.sum_incident(spring_products_.data(), ring, block, sum);
    const std::size_t first = block * kSpringBlock;
    const std::size_t count = std::min(kSpringBlock, n_ - first);
#if defined(CLOTHLAB_FLOAT_LANES)
    if constexpr (std::is_same_v<Real, float> && Shifted) {
      if (count == kSpringBlock) {  // as the grid's kernel: <u, q> widened to double lanes
        const Floats inverse_mass = load_floats(inverse_mass_ + first);
        const LaneMask active = greater(inverse_mass, zero_floats());
        Floats u_dot_q = zero_floats();
        for (std::size_t k = 0; k < 3; ++k) {
          const std::size_t at = k * stride_ + first;
          const Floats u_k = load_floats(u + at);
          const Floats value = keep(active, u_k + inverse_mass * load_floats(sum[k]));
          store_floats(out + at, value);
          u_dot_q = u_dot_q + u_k * value;
        }
        add_widened(load_floats(mass_.data() + first) * u_dot_q, dots);
        continue;
      }
    }
#endif
    for (std::size_t l = 0; l < count; ++l) {
      const std::size_t i = first + l;
      const Real inverse_mass = inverse_mass_[i];
      Real term = 0;
      for (std::size_t k = 0; k < 3; ++k) {
        const std::size_t at = k * stride_ + i;
        if (inverse_mass == Real(0)) {
          out[at] = Real(0);
        } else if constexpr (Shifted) {
          out[at] = u[at] + inverse_mass * sum[k][l];
          term += u[at] * out[at];
        } else {
          out[at] = inverse_mass * sum[k][l];
        }
      }
      if constexpr (Shifted) dot += double{mass_[i] * term};
    }
  }
#if defined(CLOTHLAB_FLOAT_LANES)
  dot += lane_sum(dots);
#endif
  return dot;
}

template <class Real>
template <JacobianForm Form, bool Shifted>
void SpringJacobian<Real>::list_apply(const Real* x, const Real* v, const Weights& w, const Real* u,
                                      Real* out) const {
  if constexpr (Shifted) {  // the cg-step product, at the linearisation, tile by tile
    const SpringLanes<Real>& lanes = *spring_lanes_;
    const auto c_x = static_cast<Real>(w.c_x), c_v = static_cast<Real>(w.damped ? w.c_v : 0.0);
    lanes.sweep(
        threads_, parallel_, SlotBuffers<Real>{spring_products_.data(), spring_rings_.data()},
        [&](std::size_t begin, std::size_t end, Real* product, std::size_t product_stride) {
          lanes.definite_products(x, spring_inverse_length_.data(), c_x, c_v, u, inverse_mass_,
                                  stride_, begin, end, product, product_stride);
        },
        [&](std::size_t tile, std::size_t begin, std::size_t end, const Real* ring, const Real*) {
          row_dots_[tile] = list_gather_blocks<true>(u, out, ring, begin, end);
        });
  } else {
    Weights form = w;
    form.definite = Form == JacobianForm::kDefinite;
    list_spring_products(u, [&](uint32_t spring, Real* m) {
      double block[9];
      spring_block(x, v, spring, form, block);
      for (std::size_t k = 0; k < 9; ++k) m[k] = static_cast<Real>(block[k]);
    });
    const std::size_t blocks = spring_lanes_->particle_blocks();
#pragma omp parallel for schedule(static) num_threads(threads_) if (parallel_)
    for (std::ptrdiff_t chunk = 0; chunk < chunks_of(n_); ++chunk) {
      const std::size_t begin = static_cast<std::size_t>(chunk) * kChunkBlocks;
      list_gather_blocks<false>(u, out, nullptr, begin, std::min(blocks, begin + kChunkBlocks));
    }
  }
}

template <class Real>
void SpringJacobian<Real>::list_linearise(const Real* x) const {
  const SpringLanes<Real>& lanes = *spring_lanes_;
  const std::size_t blocks = lanes.spring_blocks();
  const auto chunks = static_cast<std::ptrdiff_t>((blocks + kChunkBlocks - 1) / kChunkBlocks);
#pragma omp parallel for schedule(static) num_threads(threads_) if (parallel_)
  for (std::ptrdiff_t chunk = 0; chunk < chunks; ++chunk) {
    const std::size_t begin = static_cast<std::size_t>(chunk) * kChunkBlocks;
    lanes.inverse_lengths(x, stride_, begin, std::min(blocks, begin + kChunkBlocks),
                          spring_inverse_length_.data());
  }
}

template void SpringJacobian<float>::list_apply<JacobianForm::kExact, false>(
    const float*, const float*, const Weights&, const float*, float*) const;
template void SpringJacobian<float>::list_apply<JacobianForm::kDefinite, false>(
    const float*, const float*, const Weights&, const float*, float*) const;
template void SpringJacobian<float>::list_apply<JacobianForm::kDefinite, true>(
    const float*, const float*, const Weights&, const float*, float*) const;
template void SpringJacobian<double>::list_apply<JacobianForm::kExact, false>(
    const double*, const double*, const Weights&, const double*, double*) const;
template void SpringJacobian<double>::list_apply<JacobianForm::kDefinite, false>(
    const double*, const double*, const Weights&, const double*, double*) const;
template void SpringJacobian<double>::list_apply<JacobianForm::kDefinite, true>(
    const double*, const double*, const Weights&, const double*, double*) const;
template void SpringJacobian<float>::list_linearise(const float*) const;
template void SpringJacobian<double>::list_linearise(const double*) const;

}  // namespace clothlab::detail::inline CLOTHLAB_SIMD_NAMESPACE
