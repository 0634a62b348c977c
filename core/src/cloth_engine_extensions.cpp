// The host extensions of ClothEngine (clothlab/ext/): the topology and the grid it lies on (on
// the grid path alone), the analytic spring Jacobian and its definite form, the fused CG sweeps
// on it, deterministic reductions and the external forces alone, and the thread count the
// plugin may use.
#include <clothlab/ext/attachment_targets.h>
#include <clothlab/ext/cg_step.h>
#include <clothlab/ext/contacts.h>
#include <clothlab/ext/definite_jacobian.h>
#include <clothlab/ext/external_forces.h>
#include <clothlab/ext/reductions.h>
#include <clothlab/ext/threads.h>

#include <cmath>
#include <cstring>
#include <new>

#include "cloth_engine.hpp"
#include "simd_namespace.hpp"

namespace clothlab::detail::inline CLOTHLAB_SIMD_NAMESPACE {
namespace {

// Running out of memory in a callback (the first topology or jacobian call builds its data) is a
// status, never an exception across the ABI.
template <class Body>
clothlab_status status_of(Body&& body) noexcept {
  try {
    body();
    return CLOTHLAB_OK;
  } catch (const std::bad_alloc&) {
    return CLOTHLAB_ERROR_OUT_OF_MEMORY;
  }
}

clothlab_topology topology_view(const ClothModel& model) {
  clothlab_topology out{};
  out.struct_size = sizeof out;
  out.particle_count = model.particle_count;
  out.spring_count = static_cast<uint32_t>(model.spring_count());
  out.triangle_count = static_cast<uint32_t>(model.triangle_count());
  out.first = model.first.data();
  out.second = model.second.data();
  out.rest_length = model.rest_length.data();
  out.ks = model.ks.data();
  out.kd = model.kd.data();
  out.family = model.family.data();
  out.triangles = model.triangles.data();
  out.adjacency_offsets = model.adjacency_offsets.data();
  out.adjacent_springs = model.adjacent_springs.data();
  out.spring_color_count = model.spring_colors.count();
  out.spring_color_offsets = model.spring_colors.offsets.data();
  out.spring_color_members = model.spring_colors.members.data();
  out.particle_color_count = model.particle_colors.count();
  out.particle_color_offsets = model.particle_colors.offsets.data();
  out.particle_color_members = model.particle_colors.members.data();
  return out;
}

}  // namespace

template <class Real>
const SpringJacobian<Real>& ClothEngine<Real>::jacobian() {
  if (!jacobian_) {
    jacobian_ = std::make_unique<SpringJacobian<Real>>(scene_, topology(), inverse_mass_.data(),
                                                       stride_, velocity_forces_, threads_,
                                                       parallel_, !on_grid_path());
  }
  return *jacobian_;
}

template <class Real>
const void* ClothEngine<Real>::get_extension_callback(void* context, const char* id) {
  static constexpr clothlab_topology_extension topology_table{&topology_callback};
  static constexpr clothlab_grid_extension grid_table{&grid_callback};
  using Jacobian = SpringJacobian<Real>;
  static constexpr clothlab_jacobian_extension jacobian_table{
      &jacobian_reserve_callback, &jacobian_apply_callback<false>,
      &jacobian_blocks_callback<&Jacobian::diagonal_blocks>, &jacobian_pattern_callback,
      &jacobian_blocks_callback<&Jacobian::blocks>};
  static constexpr clothlab_definite_jacobian_extension definite_jacobian_table{
      &jacobian_apply_callback<true>,
      &jacobian_blocks_callback<&Jacobian::diagonal_blocks_definite>};
  static constexpr clothlab_definite_jacobian_2_extension definite_jacobian_2_table{
      &jacobian_apply_callback<true>,
      &jacobian_blocks_callback<&Jacobian::diagonal_blocks_definite>,
      &jacobian_blocks_callback<&Jacobian::blocks_definite>};
  static constexpr clothlab_cg_step_extension cg_step_table{
      &cg_linearise_callback, &cg_product_callback, &cg_update_callback};
  static constexpr clothlab_reductions_extension reductions_table{&dot_callback, &mass_dot_callback,
                                                                  &max_abs_callback};
  static constexpr clothlab_external_forces_extension external_table{&external_callback,
                                                                     &depends_on_position_callback};
  static constexpr clothlab_external_forces_2_extension external_2_table{
      &external_callback, &depends_on_position_callback, &external_rows_callback,
      &depends_on_velocity_callback};
  static constexpr clothlab_threads_extension threads_table{&threads_callback};
  static constexpr clothlab_contacts_extension contacts_table{&contacts_resolve_callback};
  static constexpr clothlab_attachment_targets_extension attachments_table{
      &attachments_count_callback, &attachments_move_callback};
  if (id == nullptr) return nullptr;
  if (std::strcmp(id, CLOTHLAB_EXT_TOPOLOGY) == 0) return &topology_table;
  // The spring-list path has no grid: an integrator that needs one refuses a mesh when it finds
  // the grid missing.
  if (std::strcmp(id, CLOTHLAB_EXT_GRID) == 0)
    return static_cast<const ClothEngine*>(context)->on_grid_path() ? &grid_table : nullptr;
  if (std::strcmp(id, CLOTHLAB_EXT_JACOBIAN) == 0) return &jacobian_table;
  if (std::strcmp(id, CLOTHLAB_EXT_DEFINITE_JACOBIAN) == 0) return &definite_jacobian_table;
  if (std::strcmp(id, CLOTHLAB_EXT_DEFINITE_JACOBIAN_2) == 0) return &definite_jacobian_2_table;
  if (std::strcmp(id, CLOTHLAB_EXT_CG_STEP) == 0) return &cg_step_table;
  if (std::strcmp(id, CLOTHLAB_EXT_REDUCTIONS) == 0) return &reductions_table;
  if (std::strcmp(id, CLOTHLAB_EXT_EXTERNAL_FORCES) == 0) return &external_table;
  if (std::strcmp(id, CLOTHLAB_EXT_EXTERNAL_FORCES_2) == 0)
    return static_cast<const ClothEngine*>(context)->offers_external_rows() ? &external_2_table
                                                                            : nullptr;
  if (std::strcmp(id, CLOTHLAB_EXT_THREADS) == 0) return &threads_table;
  if (std::strcmp(id, CLOTHLAB_EXT_CONTACTS) == 0) return &contacts_table;
  if (std::strcmp(id, CLOTHLAB_EXT_ATTACHMENT_TARGETS) == 0) return &attachments_table;
  return nullptr;
}

// -------------------------------------------------------------------- threads

template <class Real>
uint32_t ClothEngine<Real>::threads_callback(void* context) {
  return static_cast<uint32_t>(static_cast<const ClothEngine*>(context)->threads_);
}

// ------------------------------------------------- contacts and attachments

template <class Real>
clothlab_status ClothEngine<Real>::contacts_resolve_callback(void* context, double t, void* x,
                                                             void* v) {
  return static_cast<ClothEngine*>(context)->resolve_contacts(t, x, v);
}

template <class Real>
uint32_t ClothEngine<Real>::attachments_count_callback(void* context) {
  return static_cast<const ClothEngine*>(context)->attachment_count();
}

template <class Real>
clothlab_status ClothEngine<Real>::attachments_move_callback(void* context, double t, void* x,
                                                             void* v) {
  return static_cast<ClothEngine*>(context)->move_attached(t, x, v);
}

// ------------------------------------------------------------------- topology

template <class Real>
clothlab_status ClothEngine<Real>::topology_callback(void* context, clothlab_topology* out) {
  if (out == nullptr || out->struct_size < sizeof(clothlab_topology))
    return CLOTHLAB_ERROR_INVALID_ARGUMENT;
  *out = topology_view(static_cast<ClothEngine*>(context)->topology());
  return CLOTHLAB_OK;
}

template <class Real>
clothlab_status ClothEngine<Real>::grid_callback(void* context, clothlab_grid* out) {
  if (out == nullptr || out->struct_size < sizeof(clothlab_grid))
    return CLOTHLAB_ERROR_INVALID_ARGUMENT;
  const auto* self = static_cast<const ClothEngine*>(context);
  if (!self->on_grid_path()) return CLOTHLAB_ERROR_UNSUPPORTED;
  clothlab_grid grid{};
  grid.struct_size = sizeof grid;
  grid.rows = self->model_->grid->rows;
  grid.cols = self->model_->grid->cols;
  grid.spring_color_count = static_cast<uint32_t>(self->grid_colors_.size());
  grid.column_spacing = self->scene_.column_spacing();
  grid.row_spacing = self->scene_.row_spacing();
  grid.spring_colors = self->grid_colors_.data();
  *out = grid;
  return CLOTHLAB_OK;
}

// ------------------------------------------------------------------- jacobian

template <class Real>
clothlab_status ClothEngine<Real>::jacobian_reserve_callback(void* context) {
  return status_of([&] { (void)static_cast<ClothEngine*>(context)->jacobian(); });
}

template <class Real>
template <bool Definite>
clothlab_status ClothEngine<Real>::jacobian_apply_callback(void* context, double, const void* x,
                                                           const void* v, double c_x, double c_v,
                                                           const void* u, void* out) {
  if (x == nullptr || u == nullptr || out == nullptr || out == u || out == x || out == v)
    return CLOTHLAB_ERROR_INVALID_ARGUMENT;
  return status_of([&] {
    const SpringJacobian<Real>& jacobian = static_cast<ClothEngine*>(context)->jacobian();
    const auto* xs = static_cast<const Real*>(x);
    const auto* vs = static_cast<const Real*>(v);
    if constexpr (Definite)
      jacobian.apply_definite(xs, vs, c_x, c_v, static_cast<const Real*>(u),
                              static_cast<Real*>(out));
    else
      jacobian.apply(xs, vs, c_x, c_v, static_cast<const Real*>(u), static_cast<Real*>(out));
  });
}

template <class Real>
clothlab_status ClothEngine<Real>::jacobian_pattern_callback(void* context,
                                                             clothlab_block_pattern* out) {
  if (out == nullptr || out->struct_size < sizeof(clothlab_block_pattern))
    return CLOTHLAB_ERROR_INVALID_ARGUMENT;
  return status_of([&] { *out = static_cast<ClothEngine*>(context)->jacobian().pattern(); });
}

template <class Real>
template <typename ClothEngine<Real>::BlockMethod Method>
clothlab_status ClothEngine<Real>::jacobian_blocks_callback(void* context, double, const void* x,
                                                            const void* v, double c_x, double c_v,
                                                            double* out) {
  if (x == nullptr || out == nullptr) return CLOTHLAB_ERROR_INVALID_ARGUMENT;
  return status_of([&] {
    const SpringJacobian<Real>& jacobian = static_cast<ClothEngine*>(context)->jacobian();
    (jacobian.*Method)(static_cast<const Real*>(x), static_cast<const Real*>(v), c_x, c_v, out);
  });
}

// -------------------------------------------------------------------- cg-step

template <class Real>
clothlab_status ClothEngine<Real>::cg_linearise_callback(void* context, double, const void* x,
                                                         const void* v, double c_x, double c_v) {
  if (x == nullptr) return CLOTHLAB_ERROR_INVALID_ARGUMENT;
  return status_of([&] {
    static_cast<ClothEngine*>(context)->jacobian().linearise_definite(
        static_cast<const Real*>(x), static_cast<const Real*>(v), c_x, c_v);
  });
}

template <class Real>
clothlab_status ClothEngine<Real>::cg_product_callback(void* context, double alpha, double beta,
                                                       const void* z, void* p, void* solution,
                                                       void* q, double* p_dot_q) {
  if (p == nullptr || q == nullptr || p_dot_q == nullptr || q == p ||
      (z != nullptr && (solution == nullptr || z == p || z == q || solution == p || solution == q ||
                        solution == z)))
    return CLOTHLAB_ERROR_INVALID_ARGUMENT;
  auto* self = static_cast<ClothEngine*>(context);
  bool linearised = false;
  const clothlab_status status = status_of([&] {
    const SpringJacobian<Real>& jacobian = self->jacobian();
    Real* const ps = static_cast<Real*>(p);
    const typename SpringJacobian<Real>::Direction direction{
        alpha, beta, static_cast<const Real*>(z), static_cast<Real*>(solution)};
    const bool fused = z != nullptr && jacobian.fuses_direction();
    if (z != nullptr && !fused)
      self->cg_direction(static_cast<Real>(alpha), static_cast<Real>(beta), direction.z, ps,
                         direction.solution);
    linearised = jacobian.product_definite_dot(ps, static_cast<Real*>(q), *p_dot_q,
                                               fused ? &direction : nullptr);
  });
  if (status != CLOTHLAB_OK) return status;
  return linearised ? CLOTHLAB_OK : CLOTHLAB_ERROR_INVALID_ARGUMENT;
}

// One pass over the active chunks; each chunk's two sums in a fixed order, then the chunks in
// order, as chunked_sum: the same bits for any thread count.
template <class Real>
clothlab_status ClothEngine<Real>::cg_update_callback(void* context, double alpha, const void* q,
                                                      const void* diagonal,
                                                      const void* off_diagonal, void* r, void* z,
                                                      double* r_dot_r, double* r_dot_z) {
  if (q == nullptr || diagonal == nullptr || off_diagonal == nullptr || r == nullptr ||
      z == nullptr || r_dot_r == nullptr || r_dot_z == nullptr)
    return CLOTHLAB_ERROR_INVALID_ARGUMENT;
  auto* self = static_cast<ClothEngine*>(context);
  const std::size_t stride = self->stride_;
  const Real a = static_cast<Real>(alpha);
  const Real* __restrict const qs = static_cast<const Real*>(q);
  const Real* __restrict const bd = static_cast<const Real*>(diagonal);
  const Real* __restrict const bo = static_cast<const Real*>(off_diagonal);
  Real* __restrict const rs = static_cast<Real*>(r);
  Real* __restrict const zs = static_cast<Real*>(z);
  const Real* __restrict const mass = self->real_mass_.data();
  const auto chunks = static_cast<std::ptrdiff_t>(self->active_chunks_.size());
#pragma omp parallel for schedule(static) num_threads(self->threads_) if (self->parallel_)
  for (std::ptrdiff_t chunk = 0; chunk < chunks; ++chunk) {
    const std::size_t begin = self->active_chunks_[chunk].begin;
    const std::size_t end = self->active_chunks_[chunk].end;
    double rr = 0.0, rz = 0.0;
#pragma omp simd reduction(+ : rr, rz)
    for (std::size_t i = begin; i < end; ++i) {
      Real residual[3];
      for (std::size_t k = 0; k < 3; ++k) {
        const std::size_t e = k * stride + i;
        residual[k] = rs[e] - a * qs[e];
        rs[e] = residual[k];
      }
      const Real b00 = bd[i], b11 = bd[stride + i], b22 = bd[2 * stride + i];
      const Real b01 = bo[i], b02 = bo[stride + i], b12 = bo[2 * stride + i];
      const Real z0 = b00 * residual[0] + b01 * residual[1] + b02 * residual[2];
      const Real z1 = b01 * residual[0] + b11 * residual[1] + b12 * residual[2];
      const Real z2 = b02 * residual[0] + b12 * residual[1] + b22 * residual[2];
      zs[i] = z0, zs[stride + i] = z1, zs[2 * stride + i] = z2;
      // Each particle's terms in the system's precision, summed in double.
      rr += double{mass[i] * (residual[0] * residual[0] + residual[1] * residual[1] +
                              residual[2] * residual[2])};
      rz += double{mass[i] * (residual[0] * z0 + residual[1] * z1 + residual[2] * z2)};
    }
    self->chunk_sums_[chunk] = rr;
    self->chunk_sums_z_[chunk] = rz;
  }
  double total_rr = 0.0, total_rz = 0.0;
  for (std::size_t chunk = 0; chunk < self->chunk_sums_.size(); ++chunk) {
    total_rr += self->chunk_sums_[chunk];
    total_rz += self->chunk_sums_z_[chunk];
  }
  *r_dot_r = total_rr;
  *r_dot_z = total_rz;
  return CLOTHLAB_OK;
}

template <class Real>
void ClothEngine<Real>::cg_direction(Real alpha, Real beta, const Real* z, Real* p,
                                     Real* solution) {
  const Real* __restrict const zs = z;
  Real* __restrict const ps = p;
  Real* __restrict const xs = solution;
  const auto chunks = static_cast<std::ptrdiff_t>(active_chunks_.size());
#pragma omp parallel for schedule(static) num_threads(threads_) if (parallel_)
  for (std::ptrdiff_t chunk = 0; chunk < chunks; ++chunk) {
    for (std::size_t k = 0; k < 3; ++k) {
      const std::size_t begin = k * stride_ + active_chunks_[chunk].begin;
      const std::size_t end = k * stride_ + active_chunks_[chunk].end;
#pragma omp simd
      for (std::size_t e = begin; e < end; ++e) {
        xs[e] += alpha * ps[e];
        ps[e] = zs[e] + beta * ps[e];
      }
    }
  }
}

// ----------------------------------------------------------------- reductions

// Each chunk sums into 8 interleaved partial sums (element i into lane i mod 8 of its
// chunk), combined pairwise, then the chunks in order: vectorised, and the chunks are fixed
// by the active ranges, so the result does not depend on the thread count.
template <class Real>
template <class Term>
double ClothEngine<Real>::chunked_sum(Term&& term) {
  constexpr std::size_t kLanes = 8;
  const auto chunks = static_cast<std::ptrdiff_t>(active_chunks_.size());
#pragma omp parallel for schedule(static) num_threads(threads_) if (parallel_)
  for (std::ptrdiff_t chunk = 0; chunk < chunks; ++chunk) {
    const std::size_t begin = active_chunks_[chunk].begin, end = active_chunks_[chunk].end;
    double lanes[kLanes] = {};
    for (std::size_t k = 0; k < 3; ++k) {
      const std::size_t shift = k * stride_;
      std::size_t i = begin;
      for (; i + kLanes <= end; i += kLanes) {
#pragma omp simd
        for (std::size_t l = 0; l < kLanes; ++l) lanes[l] += term(shift + i + l, i + l);
      }
      for (std::size_t l = 0; i < end; ++i, ++l) lanes[l] += term(shift + i, i);
    }
    chunk_sums_[chunk] = ((lanes[0] + lanes[1]) + (lanes[2] + lanes[3])) +
                         ((lanes[4] + lanes[5]) + (lanes[6] + lanes[7]));
  }
  double total = 0.0;
  for (const double sum : chunk_sums_) total += sum;
  return total;
}

template <class Real>
double ClothEngine<Real>::dot_callback(void* context, const void* a, const void* b) {
  const Real* p = static_cast<const Real*>(a);
  const Real* q = static_cast<const Real*>(b);
  return static_cast<ClothEngine*>(context)->chunked_sum(
      [&](std::size_t element, std::size_t) { return double{p[element]} * double{q[element]}; });
}

template <class Real>
double ClothEngine<Real>::mass_dot_callback(void* context, const void* a, const void* b) {
  auto* self = static_cast<ClothEngine*>(context);
  const Real* p = static_cast<const Real*>(a);
  const Real* q = static_cast<const Real*>(b);
  const double* mass = self->mass_.data();
  return self->chunked_sum([&](std::size_t element, std::size_t particle) {
    return double{p[element]} * double{q[element]} * mass[particle];
  });
}

template <class Real>
double ClothEngine<Real>::max_abs_callback(void* context, const void* a) {
  auto* self = static_cast<ClothEngine*>(context);
  const Real* p = static_cast<const Real*>(a);
  const auto chunks = static_cast<std::ptrdiff_t>(self->active_chunks_.size());
#pragma omp parallel for schedule(static) num_threads(self->threads_) if (self->parallel_)
  for (std::ptrdiff_t chunk = 0; chunk < chunks; ++chunk) {
    double worst = 0.0;
    for (std::size_t k = 0; k < 3; ++k) {
      const Real* component = p + k * self->stride_;
      for (std::size_t i = self->active_chunks_[chunk].begin; i < self->active_chunks_[chunk].end;
           ++i) {
        const double value = std::fabs(double{component[i]});
        if (value > worst || std::isnan(value)) worst = value;  // a NaN stays: solvers see it
      }
    }
    self->chunk_sums_[chunk] = worst;
  }
  double worst = 0.0;
  for (const double value : self->chunk_sums_)
    if (value > worst || std::isnan(value)) worst = value;
  return worst;
}

// ------------------------------------------------------------ external forces

template <class Real>
clothlab_status ClothEngine<Real>::external_callback(void* context, double, const void* x,
                                                     void* a) {
  if (x == nullptr || a == nullptr || x == a) return CLOTHLAB_ERROR_INVALID_ARGUMENT;
  // The air (clothlab/ext/air.h) at the system's current velocities: the extension takes none.
  auto* self = static_cast<ClothEngine*>(context);
  const bool finite =
      self->general_ ? self->general_->evaluate_external(static_cast<const Real*>(x),
                                                         self->v_.data(), static_cast<Real*>(a))
                     : self->forces_->evaluate_external(static_cast<const Real*>(x),
                                                        self->v_.data(), static_cast<Real*>(a));
  return finite ? CLOTHLAB_OK : CLOTHLAB_ERROR_NUMERICAL;
}

template <class Real>
clothlab_status ClothEngine<Real>::external_rows_callback(void* context, double, const void* x,
                                                          void* a, uint32_t row_begin,
                                                          uint32_t row_end, uint32_t slot) {
  auto* self = static_cast<ClothEngine*>(context);
  if (x == nullptr || a == nullptr || x == a || !self->offers_external_rows() ||
      row_begin > row_end || row_end > self->scene_.rows ||
      slot >= static_cast<uint32_t>(self->forces_->thread_slots()))
    return CLOTHLAB_ERROR_INVALID_ARGUMENT;
  const bool finite = self->forces_->evaluate_external_rows(static_cast<int>(slot), row_begin,
                                                            row_end, static_cast<const Real*>(x),
                                                            self->v_.data(), static_cast<Real*>(a));
  return finite ? CLOTHLAB_OK : CLOTHLAB_ERROR_NUMERICAL;
}

template <class Real>
int32_t ClothEngine<Real>::depends_on_velocity_callback(void* context) {
  const auto* self = static_cast<const ClothEngine*>(context);
  return (self->forces_ ? self->forces_->has_air() : self->general_->has_cell_forces()) ? 1 : 0;
}

template <class Real>
int32_t ClothEngine<Real>::depends_on_position_callback(void* context) {
  const auto* self = static_cast<const ClothEngine*>(context);
  return (self->forces_ ? self->forces_->has_cell_forces() : self->general_->has_cell_forces()) ? 1
                                                                                                : 0;
}

template class ClothEngine<float>;
template class ClothEngine<double>;

}  // namespace clothlab::detail::inline CLOTHLAB_SIMD_NAMESPACE
