#include "spring_jacobian.hpp"

#include <omp.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <span>

#include "simd_namespace.hpp"

namespace clothlab::detail::inline CLOTHLAB_SIMD_NAMESPACE {
namespace {

constexpr std::size_t kParticleChunk = 2048;  // particles per thread work item, as the vector ops
constexpr std::size_t kMargin = 16;           // zeros left of a scratch row's column 0

}  // namespace

template <class Real>
SpringJacobian<Real>::SpringJacobian(const Scene& scene, const ClothModel& topology,
                                     const Real* inverse_mass, std::size_t stride, bool damping,
                                     int threads, bool parallel, bool spring_list)
    : topology_(topology),
      spring_list_(spring_list),
      inverse_mass_(inverse_mass),
      stride_(stride),
      n_(topology.particle_count),
      rows_(spring_list ? 0 : scene.rows),
      cols_(spring_list ? 0 : scene.cols),
      damping_(damping),
      threads_(threads),
      parallel_(parallel),
      span_(kMargin + (cols_ + kMargin + 15) / 16 * 16),
      product_rows_(static_cast<std::size_t>(threads) * 3 * span_),
      mass_(topology.particle_count),
      row_dots_(spring_list ? (n_ + kParticleChunk - 1) / kParticleChunk : rows_, 0.0) {
  for (std::size_t i = 0; i < n_; ++i)
    mass_[i] = inverse_mass[i] > Real(0) ? Real(1) / inverse_mass[i] : Real(0);
  if (spring_list) {
    spring_lanes_.emplace(topology, damping, kParticleChunk / kSpringBlock);
    spring_products_ = AlignedBuffer<Real>(3 * spring_lanes_->slots());
    spring_rings_ =
        AlignedBuffer<Real>(static_cast<std::size_t>(threads) * 3 * spring_lanes_->ring_slots());
    spring_inverse_length_ = AlignedBuffer<Real>(spring_lanes_->slots());
  }
  const std::span<const Stencil> grid_stencils =
      spring_list ? std::span<const Stencil>() : std::span<const Stencil>(kProvotStencils);
  for (const Stencil& stencil : grid_stencils) {  // as build_grid_model lists the springs
    const SpringFamily& law = scene.*stencil.family;
    const StencilExtent extent = stencil_extent(stencil, scene.rows, scene.cols);
    if ((law.ks == 0.0 && law.kd == 0.0) || extent.count() == 0) continue;
    stencils_.push_back({extent, stencil.row_step, stencil.col_step,
                         static_cast<Real>(stencil_rest_length(scene, stencil)),
                         static_cast<Real>(law.ks), static_cast<Real>(law.kd)});
  }
#if defined(CLOTHLAB_FLOAT_LANES)
  // On 8 lanes too: the fused sweep stores nothing under a mask but at a row's edges (a masked
  // store is microcoded on some AVX2 CPUs, which made it slower than the separate products).
  definite_kernel_ = std::is_same_v<Real, float> && stencils_.size() == kProvotStencils.size();
  if (definite_kernel_) {
    ends_rows_ = AlignedBuffer<Real>(static_cast<std::size_t>(threads) * 6 * span_);
    plane_ = (n_ + 15) / 16 * 16;
    inverse_lengths_ = AlignedBuffer<Real>(stencils_.size() * plane_);
  }
#endif
  const std::vector<uint32_t>& offsets = topology.adjacency_offsets;
  row_offsets_.assign(n_ + 1, 0);
  entry_slot_.resize(topology.adjacent_springs.size());
  diagonal_slot_.resize(n_);
  entry_partner_.resize(topology.adjacent_springs.size());
  std::vector<uint32_t> row;
  for (uint32_t i = 0; i < n_; ++i) {
    row.assign(1, i);
    for (uint32_t e = offsets[i]; e < offsets[i + 1]; ++e)
      row.push_back(partner(i, topology.adjacent_springs[e]));
    std::sort(row.begin(), row.end());
    row.erase(std::unique(row.begin(), row.end()), row.end());
    const auto base = static_cast<uint32_t>(columns_.size());
    const auto slot = [&](uint32_t column) {
      return base +
             static_cast<uint32_t>(std::lower_bound(row.begin(), row.end(), column) - row.begin());
    };
    diagonal_slot_[i] = slot(i);
    for (uint32_t e = offsets[i]; e < offsets[i + 1]; ++e) {
      entry_partner_[e] = partner(i, topology.adjacent_springs[e]);
      entry_slot_[e] = slot(entry_partner_[e]);
    }
    columns_.insert(columns_.end(), row.begin(), row.end());
    row_offsets_[i + 1] = static_cast<uint32_t>(columns_.size());
  }
  entry_mirror_slot_.resize(topology.adjacent_springs.size());
  for (uint32_t i = 0; i < n_; ++i)
    for (uint32_t e = offsets[i]; e < offsets[i + 1]; ++e) {
      const uint32_t j = entry_partner_[e];
      const auto first = columns_.begin() + row_offsets_[j];
      const auto last = columns_.begin() + row_offsets_[j + 1];
      entry_mirror_slot_[e] =
          static_cast<uint32_t>(std::lower_bound(first, last, i) - columns_.begin());
    }
}

template <class Real>
template <class Body>
void SpringJacobian<Real>::for_chunks(std::size_t count, Body&& body) const {
  const auto chunks = static_cast<std::ptrdiff_t>((count + kParticleChunk - 1) / kParticleChunk);
#pragma omp parallel for schedule(static) num_threads(threads_) if (parallel_)
  for (std::ptrdiff_t chunk = 0; chunk < chunks; ++chunk) {
    const std::size_t begin = static_cast<std::size_t>(chunk) * kParticleChunk;
    body(begin, std::min(count, begin + kParticleChunk));
  }
}

template <class Real>
template <class Body>
void SpringJacobian<Real>::for_particles(Body&& body) const {
  for_chunks(n_, [&](std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i) body(static_cast<uint32_t>(i));
  });
}

template <class Real>
void SpringJacobian<Real>::spring_block(const Real* x, const Real* v, uint32_t spring,
                                        const Weights& w, double* m) const {
  const uint32_t i = topology_.first[spring];
  const uint32_t j = topology_.second[spring];
  double d[3], dv[3] = {0, 0, 0};
  for (std::size_t k = 0; k < 3; ++k) {
    d[k] = double{x[k * stride_ + j]} - double{x[k * stride_ + i]};
    if (w.damped) dv[k] = double{v[k * stride_ + j]} - double{v[k * stride_ + i]};
  }
  const double squared = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
  if (squared == 0.0) {  // the force pass gives a zero-length spring no force
    std::fill(m, m + 9, 0.0);
    return;
  }
  const double inverse_length = 1.0 / std::sqrt(squared);
  const double u[3] = {d[0] * inverse_length, d[1] * inverse_length, d[2] * inverse_length};
  const double ks = topology_.ks[spring];
  const double kd = w.damped ? topology_.kd[spring] : 0.0;
  const double ratio = topology_.rest_length[spring] * inverse_length;  // l0 / l
  if (w.definite) {  // ks (t (I - u u^T) + u u^T), t = max(0, 1 - l0/l); kd u u^T
    const double transverse = std::max(0.0, 1.0 - ratio);
    for (std::size_t r = 0; r < 3; ++r)
      for (std::size_t c = 0; c < 3; ++c) {
        const double uu = u[r] * u[c];
        m[3 * r + c] =
            w.c_x * ks * ((r == c ? transverse : 0.0) + (1.0 - transverse) * uu) + w.c_v * kd * uu;
      }
    return;
  }
  // K = a I + b u u^T + (kd/l) (u (P dv)^T + s P) with s = u . dv; D = kd u u^T.
  const double s = u[0] * dv[0] + u[1] * dv[1] + u[2] * dv[2];
  const double damping_scale = kd * inverse_length;
  const double a = ks * (1.0 - ratio) + damping_scale * s;
  const double b = ks * ratio - damping_scale * s;
  const double projected_dv[3] = {dv[0] - s * u[0], dv[1] - s * u[1], dv[2] - s * u[2]};
  for (std::size_t r = 0; r < 3; ++r) {
    for (std::size_t c = 0; c < 3; ++c) {
      const double uu = u[r] * u[c];
      const double k_rc = (r == c ? a : 0.0) + b * uu + damping_scale * u[r] * projected_dv[c];
      m[3 * r + c] = w.c_x * k_rc + w.c_v * kd * uu;
    }
  }
}

template <class Real>
template <JacobianForm Form, bool Shifted>
void SpringJacobian<Real>::apply_rows(const Real* x, const Real* v, const Weights& w, const Real* u,
                                      Real* out, std::size_t begin, std::size_t end,
                                      Real* p) const {
  const std::size_t cols = cols_;
  for (std::size_t k = 0; k < 3; ++k)
    std::fill(out + k * stride_ + begin * cols, out + k * stride_ + end * cols, Real(0));
  // Springs starting in the two rows above the block reach into it.
  for (std::size_t row = begin >= 2 ? begin - 2 : 0; row < end; ++row) {
    const std::size_t base = row * cols;
    const bool own = row >= begin;
    for (const StencilSprings& stencil : stencils_) {
      if (row >= stencil.extent.row_end) continue;
      const std::size_t partner_row = row + stencil.row_step;
      const bool in_row = stencil.row_step == 0;
      const bool partner = !in_row && partner_row >= begin && partner_row < end;
      if (!own && !partner) continue;
      const std::size_t offset =
          stencil.row_step * cols + static_cast<std::size_t>(stencil.col_step);
      const bool damped = w.damped && stencil.kd > Real(0);
      const JacobianRow<Real> job{x + base,
                                  x + base + offset,
                                  damped ? v + base : nullptr,
                                  damped ? v + base + offset : nullptr,
                                  u + base,
                                  u + base + offset,
                                  inverse_mass_ + base,
                                  inverse_mass_ + base + offset,
                                  p,
                                  out + base,
                                  out + base + offset,
                                  stride_,
                                  span_,
                                  stencil.extent.col_begin,
                                  stencil.extent.col_end,
                                  stencil.rest,
                                  stencil.ks,
                                  stencil.kd,
                                  static_cast<Real>(w.c_x),
                                  static_cast<Real>(w.c_v)};
      // An in-row stencil's shifted add reads the columns after its last spring: they hold 0.
      if (in_row)
        for (std::size_t k = 0; k < 3; ++k)
          std::fill(p + k * span_ + job.col_end, p + k * span_ + cols, Real(0));
      if (own && partner) {
        if (damped)
          jacobian_row<Real, Form, true, true>(job);
        else
          jacobian_row<Real, Form, false, true>(job);
        continue;
      }
      if (damped)
        jacobian_row<Real, Form, true, false>(job);
      else
        jacobian_row<Real, Form, false, false>(job);
      for (std::size_t k = 0; k < 3; ++k) {
        const Real* __restrict product = p + k * span_;
        Real* __restrict own_row = out + k * stride_ + base;
        if (in_row) {
          const Real* __restrict back = product - stencil.col_step;
#pragma omp simd
          for (std::size_t c = 0; c < cols; ++c) own_row[c] += product[c] - back[c];
          continue;
        }
        if (own) {
#pragma omp simd
          for (std::size_t c = job.col_begin; c < job.col_end; ++c) own_row[c] += product[c];
        }
        if (partner) {
          Real* __restrict partner_row_out = out + k * stride_ + base + offset;
#pragma omp simd
          for (std::size_t c = job.col_begin; c < job.col_end; ++c)
            partner_row_out[c] -= product[c];
        }
      }
    }
    if (!own) continue;
    // Row complete: every spring reaching it starts in it or in the two rows above.
    const Real* __restrict inverse_mass = inverse_mass_ + base;
    if constexpr (Shifted) {
      finish_shifted_row(u, out, row, p);
      continue;
    }
    for (std::size_t k = 0; k < 3; ++k) {
      Real* __restrict row_out = out + k * stride_ + base;
#pragma omp simd
      for (std::size_t c = 0; c < cols; ++c)
        row_out[c] = inverse_mass[c] > Real(0) ? inverse_mass[c] * row_out[c] : Real(0);
    }
  }
}

template <class Real>
void SpringJacobian<Real>::finish_shifted_row(const Real* u, Real* out, std::size_t row,
                                              Real* scratch) const {
  const std::size_t base = row * cols_;
  u += base, out += base;
  const Real* __restrict inverse_mass = inverse_mass_ + base;
  const Real* __restrict mass = mass_.data() + base;
  const Real* __restrict u0 = u;
  const Real* __restrict u1 = u + stride_;
  const Real* __restrict u2 = u + 2 * stride_;
  Real* __restrict q0 = out;
  Real* __restrict q1 = out + stride_;
  Real* __restrict q2 = out + 2 * stride_;
  Real* __restrict terms = scratch;
#pragma omp simd
  for (std::size_t c = 0; c < cols_; ++c) {
    // Every load unconditional, then selects on values: the loop vectorises.
    const Real im = inverse_mass[c], p0 = u0[c], p1 = u1[c], p2 = u2[c];
    const bool active = im > Real(0);
    const Real a0 = active ? p0 + im * q0[c] : Real(0);
    const Real a1 = active ? p1 + im * q1[c] : Real(0);
    const Real a2 = active ? p2 + im * q2[c] : Real(0);
    q0[c] = a0, q1[c] = a1, q2[c] = a2;
    terms[c] = active ? mass[c] * (p0 * a0 + p1 * a1 + p2 * a2) : Real(0);
  }
  // Summed apart: GCC does not vectorise the float loop with a double reduction in it.
  double dot = 0.0;
#pragma omp simd reduction(+ : dot)
  for (std::size_t c = 0; c < cols_; ++c) dot += double{terms[c]};
  row_dots_[row] = dot;
}

template <class Real>
template <JacobianForm Form, bool Shifted>
void SpringJacobian<Real>::apply_form(const Real* x, const Real* v, double c_x, double c_v,
                                      const Real* u, Real* out, const Direction* direction) const {
  const Weights w{c_x, c_v, damping_ && v != nullptr};
  if (spring_list_) {
    list_apply<Form, Shifted>(x, v, w, u, out);
    return;
  }
#pragma omp parallel num_threads(threads_) if (parallel_)
  {
    const auto thread = static_cast<std::size_t>(omp_get_thread_num());
    const auto team = static_cast<std::size_t>(omp_get_num_threads());
    const std::size_t begin = rows_ * thread / team, end = rows_ * (thread + 1) / team;
    if (Shifted && Form == JacobianForm::kDefinite && definite_kernel_) {
      definite_rows(const_cast<Real*>(u), out, begin, end,
                    ends_rows_.data() + thread * 6 * span_ + kMargin, direction);
    } else {
      apply_rows<Form, Shifted>(x, v, w, u, out, begin, end,
                                product_rows_.data() + thread * 3 * span_ + kMargin);
    }
  }
}

template <class Real>
void SpringJacobian<Real>::apply(const Real* x, const Real* v, double c_x, double c_v,
                                 const Real* u, Real* out) const {
  apply_form<JacobianForm::kExact>(x, v, c_x, c_v, u, out);
}

template <class Real>
void SpringJacobian<Real>::apply_definite(const Real* x, const Real* v, double c_x, double c_v,
                                          const Real* u, Real* out) const {
  apply_form<JacobianForm::kDefinite>(x, v, c_x, c_v, u, out);
}

template <class Real>
bool SpringJacobian<Real>::product_definite_dot(Real* u, Real* q, double& dot,
                                                const Direction* direction) const {
  const Linearisation& at = linearised_;
  if (at.x == nullptr || (direction != nullptr && !definite_kernel_)) return false;
  apply_form<JacobianForm::kDefinite, true>(at.x, at.v, at.c_x, at.c_v, u, q, direction);
  dot = 0.0;
  for (const double row : row_dots_) dot += row;
  return true;
}

template <class Real>
void SpringJacobian<Real>::diagonal_blocks(const Real* x, const Real* v, double c_x, double c_v,
                                           double* out) const {
  diagonal_blocks(x, v, Weights{c_x, c_v, damping_ && v != nullptr}, out);
}

template <class Real>
void SpringJacobian<Real>::diagonal_blocks_definite(const Real* x, const Real* v, double c_x,
                                                    double c_v, double* out) const {
  diagonal_blocks(x, v, Weights{c_x, c_v, damping_ && v != nullptr, true}, out);
}

template <class Real>
void SpringJacobian<Real>::diagonal_blocks(const Real* x, const Real* v, const Weights& w,
                                           double* out) const {
  const std::vector<uint32_t>& offsets = topology_.adjacency_offsets;
  for_particles([&](uint32_t i) {
    double* block = out + 9 * std::size_t{i};
    std::fill(block, block + 9, 0.0);
    const double inverse_mass = inverse_mass_[i];
    if (inverse_mass == 0.0) return;
    for (uint32_t e = offsets[i]; e < offsets[i + 1]; ++e) {
      double m[9];
      spring_block(x, v, topology_.adjacent_springs[e], w, m);
      for (std::size_t k = 0; k < 9; ++k) block[k] -= inverse_mass * m[k];
    }
  });
}

template <class Real>
void SpringJacobian<Real>::blocks(const Real* x, const Real* v, double c_x, double c_v,
                                  double* values) const {
  blocks(x, v, Weights{c_x, c_v, damping_ && v != nullptr}, values);
}

template <class Real>
void SpringJacobian<Real>::blocks_definite(const Real* x, const Real* v, double c_x, double c_v,
                                           double* values) const {
  blocks(x, v, Weights{c_x, c_v, damping_ && v != nullptr, true}, values);
}

// Each spring's block is built once: pass 1 sums the blocks of the springs joining a pair, on
// the row of its lower particle, into both of the pair's slots (no other row writes them); pass
// 2 finishes each row alone: its off-diagonal sums times m_i^-1 (0 where the partner is pinned),
// its diagonal -m_i^-1 times their total.
template <class Real>
void SpringJacobian<Real>::blocks(const Real* x, const Real* v, const Weights& w,
                                  double* values) const {
  const std::vector<uint32_t>& offsets = topology_.adjacency_offsets;
  const auto pair_blocks = [&](uint32_t e) {
    return std::array<double*, 2>{values + 9 * std::size_t{entry_slot_[e]},
                                  values + 9 * std::size_t{entry_mirror_slot_[e]}};
  };
  for_particles([&](uint32_t i) {
    for (uint32_t e = offsets[i]; e < offsets[i + 1]; ++e) {
      if (entry_partner_[e] < i) continue;
      double m[9];
      spring_block(x, v, topology_.adjacent_springs[e], w, m);
      // The pair's first spring in the row writes its slots, a later one (two springs joining
      // the same pair) adds: no pass zeroes the table first.
      const bool first = std::find(entry_slot_.begin() + offsets[i], entry_slot_.begin() + e,
                                   entry_slot_[e]) == entry_slot_.begin() + e;
      for (double* block : pair_blocks(e))
        for (std::size_t k = 0; k < 9; ++k) block[k] = first ? m[k] : block[k] + m[k];
    }
  });
  for_particles([&](uint32_t i) {
    const double inverse_mass = inverse_mass_[i];
    double total[9] = {};
    for (uint32_t slot = row_offsets_[i]; slot < row_offsets_[i + 1]; ++slot) {
      if (slot == diagonal_slot_[i]) continue;
      double* block = values + 9 * std::size_t{slot};
      const double scale = inverse_mass_[columns_[slot]] > Real(0) ? inverse_mass : 0.0;
      for (std::size_t k = 0; k < 9; ++k) {
        total[k] += block[k];
        block[k] = scale > 0.0 ? scale * block[k] : 0.0;
      }
    }
    double* diagonal = values + 9 * std::size_t{diagonal_slot_[i]};
    for (std::size_t k = 0; k < 9; ++k)
      diagonal[k] = inverse_mass > 0.0 ? -inverse_mass * total[k] : 0.0;
  });
}

template <class Real>
clothlab_block_pattern SpringJacobian<Real>::pattern() const {
  clothlab_block_pattern out{};
  out.struct_size = sizeof out;
  out.row_count = static_cast<uint32_t>(n_);
  out.block_count = static_cast<uint32_t>(columns_.size());
  out.row_offsets = row_offsets_.data();
  out.columns = columns_.data();
  return out;
}

template class SpringJacobian<float>;
template class SpringJacobian<double>;

}  // namespace clothlab::detail::inline CLOTHLAB_SIMD_NAMESPACE
