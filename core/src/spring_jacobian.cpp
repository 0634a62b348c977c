#include "spring_jacobian.hpp"

#include <algorithm>
#include <cmath>

namespace clothlab::detail {
namespace {

constexpr std::size_t kChunk = 2048;  // particles per thread work item, as the vector ops

}  // namespace

template <class Real>
SpringJacobian<Real>::SpringJacobian(const GridTopology& topology, const Real* inverse_mass,
                                     std::size_t stride, bool damping, int threads, bool parallel)
    : topology_(topology),
      inverse_mass_(inverse_mass),
      stride_(stride),
      n_(topology.particle_count),
      damping_(damping),
      threads_(threads),
      parallel_(parallel) {
  const std::vector<uint32_t>& offsets = topology.adjacency_offsets;
  row_offsets_.assign(n_ + 1, 0);
  entry_slot_.resize(topology.adjacent_springs.size());
  diagonal_slot_.resize(n_);
  entry_partner_.resize(topology.adjacent_springs.size());
  spring_products_.resize(3 * topology.spring_count());
  for (uint32_t spring = 0; spring < topology.spring_count(); ++spring) {
    const uint32_t first = topology.first[spring], second = topology.second[spring];
    if (!runs_.empty()) {
      SpringRun& run = runs_.back();
      if (run.count < kChunk && first == run.first + run.count &&
          second == run.second + run.count) {
        ++run.count;
        continue;
      }
    }
    runs_.push_back({spring, 1, first, second});
  }
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
}

template <class Real>
template <class Body>
void SpringJacobian<Real>::for_chunks(std::size_t count, Body&& body) const {
  const auto chunks = static_cast<std::ptrdiff_t>((count + kChunk - 1) / kChunk);
#pragma omp parallel for schedule(static) num_threads(threads_) if (parallel_)
  for (std::ptrdiff_t chunk = 0; chunk < chunks; ++chunk) {
    const std::size_t begin = static_cast<std::size_t>(chunk) * kChunk;
    body(begin, std::min(count, begin + kChunk));
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
template <bool Damped>
void SpringJacobian<Real>::spring_products(const Real* x, const Real* v, const Real* u,
                                           const Weights& w, const SpringRun& run) const {
  const std::size_t springs = topology_.spring_count();
  const double* rest_length = topology_.rest_length.data() + run.spring;
  const double* ks = topology_.ks.data() + run.spring;
  const double* kd = topology_.kd.data() + run.spring;
  double* products = spring_products_.data() + run.spring;
  // Branch-free so that it vectorises; a spring with both ends pinned gets a value no row reads.
#pragma omp simd
  for (std::size_t spring = 0; spring < run.count; ++spring) {
    const std::size_t i = run.first + spring, j = run.second + spring;
    // Pinned columns are zero.
    const double i_active = inverse_mass_[i] > Real(0) ? 1.0 : 0.0;
    const double j_active = inverse_mass_[j] > Real(0) ? 1.0 : 0.0;
    double d[3], dv[3], du[3];
    for (std::size_t k = 0; k < 3; ++k) {
      d[k] = double{x[k * stride_ + j]} - double{x[k * stride_ + i]};
      dv[k] = Damped ? double{v[k * stride_ + j]} - double{v[k * stride_ + i]} : 0.0;
      du[k] = j_active * double{u[k * stride_ + j]} - i_active * double{u[k * stride_ + i]};
    }
    const double squared = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
    // The force pass gives a zero-length spring no force.
    const double inverse_length = squared > 0.0 ? 1.0 / std::sqrt(squared) : 0.0;
    const double live = squared > 0.0 ? 1.0 : 0.0;
    // M du without forming M: c_x (a du + (b (n.du) + (kd/l) (P dv).du) n) + c_v kd (n.du) n.
    const double n[3] = {d[0] * inverse_length, d[1] * inverse_length, d[2] * inverse_length};
    const double damping = Damped ? kd[spring] : 0.0;
    const double ratio = rest_length[spring] * inverse_length;
    const double s = n[0] * dv[0] + n[1] * dv[1] + n[2] * dv[2];
    const double damping_scale = damping * inverse_length;
    const double a = ks[spring] * (1.0 - ratio) + damping_scale * s;
    const double b = ks[spring] * ratio - damping_scale * s;
    const double n_du = n[0] * du[0] + n[1] * du[1] + n[2] * du[2];
    const double dv_du = dv[0] * du[0] + dv[1] * du[1] + dv[2] * du[2];
    const double projected_dv_du = dv_du - s * n_du;
    const double along =
        w.c_x * (b * n_du + damping_scale * projected_dv_du) + w.c_v * damping * n_du;
    const double across = live * w.c_x * a;
    for (std::size_t r = 0; r < 3; ++r)
      products[r * springs + spring] = across * du[r] + along * n[r];
  }
}

template <class Real>
void SpringJacobian<Real>::apply(const Real* x, const Real* v, double c_x, double c_v,
                                 const Real* u, Real* out) const {
  const Weights w{c_x, c_v, damping_ && v != nullptr};
  const std::vector<uint32_t>& offsets = topology_.adjacency_offsets;
  const double* products = spring_products_.data();
  const std::size_t springs = topology_.spring_count();
  const auto runs = static_cast<std::ptrdiff_t>(runs_.size());
#pragma omp parallel for schedule(static) num_threads(threads_) if (parallel_)
  for (std::ptrdiff_t run = 0; run < runs; ++run) {
    if (w.damped)
      spring_products<true>(x, v, u, w, runs_[static_cast<std::size_t>(run)]);
    else
      spring_products<false>(x, v, u, w, runs_[static_cast<std::size_t>(run)]);
  }
  for_particles([&](uint32_t i) {
    double sum[3] = {0, 0, 0};
    const double inverse_mass = inverse_mass_[i];
    if (inverse_mass > 0.0) {
      for (uint32_t e = offsets[i]; e < offsets[i + 1]; ++e) {
        const uint32_t spring = topology_.adjacent_springs[e];
        // Seen from the second particle du changes sign (exactly).
        if (topology_.first[spring] == i) {
          for (std::size_t r = 0; r < 3; ++r) sum[r] += products[r * springs + spring];
        } else {
          for (std::size_t r = 0; r < 3; ++r) sum[r] -= products[r * springs + spring];
        }
      }
    }
    for (std::size_t k = 0; k < 3; ++k)
      out[k * stride_ + i] = static_cast<Real>(inverse_mass * sum[k]);
  });
}

template <class Real>
void SpringJacobian<Real>::diagonal_blocks(const Real* x, const Real* v, double c_x, double c_v,
                                           double* out) const {
  const Weights w{c_x, c_v, damping_ && v != nullptr};
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
  const Weights w{c_x, c_v, damping_ && v != nullptr};
  const std::vector<uint32_t>& offsets = topology_.adjacency_offsets;
  for_particles([&](uint32_t i) {
    std::fill(values + 9 * std::size_t{row_offsets_[i]},
              values + 9 * std::size_t{row_offsets_[i + 1]}, 0.0);
    const double inverse_mass = inverse_mass_[i];
    if (inverse_mass == 0.0) return;
    double* diagonal = values + 9 * std::size_t{diagonal_slot_[i]};
    for (uint32_t e = offsets[i]; e < offsets[i + 1]; ++e) {
      double m[9];
      spring_block(x, v, topology_.adjacent_springs[e], w, m);
      const bool j_active = inverse_mass_[entry_partner_[e]] > Real(0);
      double* off_diagonal = values + 9 * std::size_t{entry_slot_[e]};
      for (std::size_t k = 0; k < 9; ++k) {
        diagonal[k] -= inverse_mass * m[k];
        if (j_active) off_diagonal[k] += inverse_mass * m[k];
      }
    }
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

}  // namespace clothlab::detail
