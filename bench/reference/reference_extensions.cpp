// The reference system's host extensions: plain serial loops, springs scattered one by one.
#include <clothlab/ext/cg_step.h>
#include <clothlab/ext/definite_jacobian.h>
#include <clothlab/ext/external_forces.h>
#include <clothlab/ext/reductions.h>

#include <algorithm>
#include <cmath>
#include <cstring>

#include "reference_system.hpp"

namespace clothlab::reference {

template <class Real>
const void* ReferenceSystem<Real>::get_extension_callback(void*, const char* id) {
  static constexpr clothlab_jacobian_extension jacobian{&jacobian_reserve, &jacobian_apply<false>,
                                                        &jacobian_diagonal<false>,
                                                        &jacobian_pattern, &jacobian_blocks<false>};
  static constexpr clothlab_definite_jacobian_extension definite_jacobian{&jacobian_apply<true>,
                                                                          &jacobian_diagonal<true>};
  static constexpr clothlab_cg_step_extension cg_step{&cg_linearise, &cg_product, &cg_update};
  static constexpr clothlab_reductions_extension reductions{&dot, &mass_dot, &max_abs};
  static constexpr clothlab_external_forces_extension external_forces{&external,
                                                                      &depends_on_position};
  static constexpr clothlab_topology_extension topology{&topology_get};
  static constexpr clothlab_grid_extension grid{&grid_get};
  if (id == nullptr) return nullptr;
  if (std::strcmp(id, CLOTHLAB_EXT_TOPOLOGY) == 0) return &topology;
  if (std::strcmp(id, CLOTHLAB_EXT_GRID) == 0) return &grid;
  if (std::strcmp(id, CLOTHLAB_EXT_JACOBIAN) == 0) return &jacobian;
  if (std::strcmp(id, CLOTHLAB_EXT_DEFINITE_JACOBIAN) == 0) return &definite_jacobian;
  if (std::strcmp(id, CLOTHLAB_EXT_CG_STEP) == 0) return &cg_step;
  if (std::strcmp(id, CLOTHLAB_EXT_REDUCTIONS) == 0) return &reductions;
  if (std::strcmp(id, CLOTHLAB_EXT_EXTERNAL_FORCES) == 0) return &external_forces;
  return nullptr;
}

namespace {

// Members grouped by colour (CSR), ascending within a colour.
void group(const std::vector<uint32_t>& color_of, std::vector<uint32_t>& offsets,
           std::vector<uint32_t>& members) {
  const uint32_t colors =
      color_of.empty() ? 0 : *std::max_element(color_of.begin(), color_of.end()) + 1;
  std::vector<std::vector<uint32_t>> by_color(colors);
  for (uint32_t item = 0; item < color_of.size(); ++item) by_color[color_of[item]].push_back(item);
  offsets.assign(1, 0);
  members.clear();
  for (const std::vector<uint32_t>& items : by_color) {
    members.insert(members.end(), items.begin(), items.end());
    offsets.push_back(static_cast<uint32_t>(members.size()));
  }
}

// The smallest colour not in `used` (a bit per colour).
uint32_t first_free(uint64_t used) {
  uint32_t color = 0;
  while (used & (uint64_t{1} << color)) ++color;
  return color;
}

}  // namespace

template <class Real>
void ReferenceSystem<Real>::build_topology(const Scene& scene) {
  Topology& t = topology_;
  for (const Spring<Real>& s : cloth_.springs()) {
    const SpringFamily& law = s.family == CLOTHLAB_SPRING_STRUCTURAL ? scene.structural
                              : s.family == CLOTHLAB_SPRING_SHEAR    ? scene.shear
                                                                     : scene.flexion;
    if (law.ks == 0.0 && law.kd == 0.0) continue;
    t.first.push_back(std::min(s.i, s.j));
    t.second.push_back(std::max(s.i, s.j));
    t.rest_length.push_back(s.rest);
    t.ks.push_back(law.ks);
    t.kd.push_back(law.kd);
    t.family.push_back(s.family);
  }
  // Column of cells by column of cells, as the engine lists them.
  for (uint32_t c = 0; c + 1 < scene.cols; ++c)
    for (uint32_t r = 0; r + 1 < scene.rows; ++r) {
      const uint32_t a = r * scene.cols + c;
      t.triangles.insert(t.triangles.end(),
                         {a, a + 1, a + scene.cols, a + 1, a + scene.cols + 1, a + scene.cols});
    }
  std::vector<std::vector<uint32_t>> touching(n_);
  for (uint32_t s = 0; s < t.first.size(); ++s) {
    touching[t.first[s]].push_back(s);
    touching[t.second[s]].push_back(s);
  }
  t.adjacency_offsets.assign(1, 0);
  for (const std::vector<uint32_t>& springs : touching) {
    t.adjacent_springs.insert(t.adjacent_springs.end(), springs.begin(), springs.end());
    t.adjacency_offsets.push_back(static_cast<uint32_t>(t.adjacent_springs.size()));
  }
  // First-fit colourings, in index order.
  std::vector<uint64_t> used_at(n_, 0);
  std::vector<uint32_t> spring_colors;
  for (uint32_t s = 0; s < t.first.size(); ++s) {
    const uint32_t color = first_free(used_at[t.first[s]] | used_at[t.second[s]]);
    spring_colors.push_back(color);
    used_at[t.first[s]] |= uint64_t{1} << color;
    used_at[t.second[s]] |= uint64_t{1} << color;
  }
  std::vector<uint32_t> particle_colors(n_, 0);
  for (uint32_t i = 0; i < n_; ++i) {
    uint64_t used = 0;
    for (uint32_t e = t.adjacency_offsets[i]; e < t.adjacency_offsets[i + 1]; ++e) {
      const uint32_t s = t.adjacent_springs[e];
      const uint32_t other = t.first[s] == i ? t.second[s] : t.first[s];
      if (other < i) used |= uint64_t{1} << particle_colors[other];
    }
    particle_colors[i] = first_free(used);
  }
  group(spring_colors, t.spring_color_offsets, t.spring_color_members);
  group(particle_colors, t.particle_color_offsets, t.particle_color_members);
  grid_.struct_size = sizeof grid_;
  grid_.rows = scene.rows;
  grid_.cols = scene.cols;
  grid_.spring_color_count = static_cast<uint32_t>(t.spring_color_offsets.size() - 1);
  grid_.column_spacing = scene.column_spacing();
  grid_.row_spacing = scene.row_spacing();
  grid_.spring_colors = nullptr;  // first-fit colours are no stencils
}

template <class Real>
clothlab_status ReferenceSystem<Real>::grid_get(void* context, clothlab_grid* out) {
  if (out == nullptr || out->struct_size < sizeof(clothlab_grid))
    return CLOTHLAB_ERROR_INVALID_ARGUMENT;
  *out = static_cast<const ReferenceSystem*>(context)->grid_;
  return CLOTHLAB_OK;
}

template <class Real>
clothlab_status ReferenceSystem<Real>::topology_get(void* context, clothlab_topology* out) {
  const auto& self = *static_cast<const ReferenceSystem*>(context);
  if (out == nullptr || out->struct_size < sizeof(clothlab_topology))
    return CLOTHLAB_ERROR_INVALID_ARGUMENT;
  const Topology& t = self.topology_;
  out->particle_count = static_cast<uint32_t>(self.n_);
  out->spring_count = static_cast<uint32_t>(t.first.size());
  out->triangle_count = static_cast<uint32_t>(t.triangles.size() / 3);
  out->first = t.first.data();
  out->second = t.second.data();
  out->rest_length = t.rest_length.data();
  out->ks = t.ks.data();
  out->kd = t.kd.data();
  out->family = t.family.data();
  out->triangles = t.triangles.data();
  out->adjacency_offsets = t.adjacency_offsets.data();
  out->adjacent_springs = t.adjacent_springs.data();
  out->spring_color_count = static_cast<uint32_t>(t.spring_color_offsets.size() - 1);
  out->spring_color_offsets = t.spring_color_offsets.data();
  out->spring_color_members = t.spring_color_members.data();
  out->particle_color_count = static_cast<uint32_t>(t.particle_color_offsets.size() - 1);
  out->particle_color_offsets = t.particle_color_offsets.data();
  out->particle_color_members = t.particle_color_members.data();
  return CLOTHLAB_OK;
}

template <class Real>
void ReferenceSystem<Real>::spring_block(const Spring<Real>& s, const Real* x, const Real* v,
                                         double c_x, double c_v, bool definite,
                                         double (&m)[9]) const {
  double d[3], dv[3] = {0, 0, 0};
  for (std::size_t k = 0; k < 3; ++k) {
    d[k] = double{x[k * stride_ + s.j]} - double{x[k * stride_ + s.i]};
    if (v != nullptr) dv[k] = double{v[k * stride_ + s.j]} - double{v[k * stride_ + s.i]};
  }
  const double l = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
  std::fill(std::begin(m), std::end(m), 0.0);
  if (l == 0.0) return;
  const double kd = v != nullptr && velocity_forces_ ? double{s.kd} : 0.0;
  const double u[3] = {d[0] / l, d[1] / l, d[2] / l};
  const double closing = u[0] * dv[0] + u[1] * dv[1] + u[2] * dv[2];
  // dF/dd = ks ((1 - l0/l) I + (l0/l) u u^T) + (kd/l) (closing I + u dv^T - 2 closing u u^T),
  // dF/d(dv) = kd u u^T. Definite: ks (max(0, 1 - l0/l) (I - u u^T) + u u^T) for dF/dd.
  const double transverse = definite ? std::max(0.0, 1.0 - s.rest / l) : 1.0 - s.rest / l;
  for (std::size_t r = 0; r < 3; ++r) {
    for (std::size_t c = 0; c < 3; ++c) {
      const double identity = r == c ? 1.0 : 0.0;
      const double hooke = s.ks * (transverse * (identity - u[r] * u[c]) + u[r] * u[c]);
      const double stiffness =
          definite
              ? hooke
              : hooke + kd / l * (closing * identity + u[r] * dv[c] - 2 * closing * u[r] * u[c]);
      m[3 * r + c] = c_x * stiffness + c_v * kd * u[r] * u[c];
    }
  }
}

template <class Real>
clothlab_status ReferenceSystem<Real>::jacobian_reserve(void*) {
  return CLOTHLAB_OK;  // everything was built with the system
}

template <class Real>
template <bool Definite>
clothlab_status ReferenceSystem<Real>::jacobian_apply(void* context, double, const void* x,
                                                      const void* v, double c_x, double c_v,
                                                      const void* u, void* out) {
  auto& self = *static_cast<ReferenceSystem*>(context);
  const Real* xs = static_cast<const Real*>(x);
  const Real* vs = static_cast<const Real*>(v);
  const Real* us = static_cast<const Real*>(u);
  std::fill(self.product_.begin(), self.product_.end(), 0.0);
  const auto direction = [&](uint32_t p, std::size_t k) {
    return self.inverse_mass_[p] == Real(0) ? 0.0 : double{us[k * self.stride_ + p]};
  };
  for (const Spring<Real>& s : self.cloth_.springs()) {
    double m[9];
    self.spring_block(s, xs, vs, c_x, c_v, Definite, m);
    for (std::size_t r = 0; r < 3; ++r) {
      double change = 0;
      for (std::size_t c = 0; c < 3; ++c)
        change += m[3 * r + c] * (direction(s.j, c) - direction(s.i, c));
      self.product_[3 * s.i + r] += change;  // dF_i = M (du_j - du_i)
      self.product_[3 * s.j + r] -= change;  // dF_j = -dF_i
    }
  }
  Real* result = static_cast<Real*>(out);
  for (std::size_t i = 0; i < self.n_; ++i)
    for (std::size_t k = 0; k < 3; ++k)
      result[k * self.stride_ + i] =
          static_cast<Real>(double{self.inverse_mass_[i]} * self.product_[3 * i + k]);
  return CLOTHLAB_OK;
}

template <class Real>
uint32_t ReferenceSystem<Real>::slot(uint32_t row, uint32_t column) const {
  const auto begin = columns_.begin() + row_offsets_[row];
  const auto end = columns_.begin() + row_offsets_[row + 1];
  return static_cast<uint32_t>(std::lower_bound(begin, end, column) - columns_.begin());
}

template <class Real>
template <bool Definite>
clothlab_status ReferenceSystem<Real>::jacobian_blocks(void* context, double, const void* x,
                                                       const void* v, double c_x, double c_v,
                                                       double* values) {
  auto& self = *static_cast<ReferenceSystem*>(context);
  std::fill(values, values + 9 * self.columns_.size(), 0.0);
  for (const Spring<Real>& s : self.cloth_.springs()) {
    double m[9];
    self.spring_block(s, static_cast<const Real*>(x), static_cast<const Real*>(v), c_x, c_v,
                      Definite, m);
    for (const auto& [row, column] : {std::pair{s.i, s.j}, std::pair{s.j, s.i}}) {
      const double weight = self.inverse_mass_[row];
      const bool column_active = self.inverse_mass_[column] != Real(0);
      for (std::size_t e = 0; e < 9; ++e) {
        values[9 * std::size_t{self.slot(row, row)} + e] -= weight * m[e];
        if (column_active) values[9 * std::size_t{self.slot(row, column)} + e] += weight * m[e];
      }
    }
  }
  return CLOTHLAB_OK;
}

template <class Real>
template <bool Definite>
clothlab_status ReferenceSystem<Real>::jacobian_diagonal(void* context, double t, const void* x,
                                                         const void* v, double c_x, double c_v,
                                                         double* out) {
  auto& self = *static_cast<ReferenceSystem*>(context);
  jacobian_blocks<Definite>(context, t, x, v, c_x, c_v, self.blocks_.data());
  for (uint32_t i = 0; i < self.n_; ++i)
    std::copy_n(self.blocks_.begin() + 9 * std::size_t{self.slot(i, i)}, 9,
                out + 9 * std::size_t{i});
  return CLOTHLAB_OK;
}

template <class Real>
clothlab_status ReferenceSystem<Real>::jacobian_pattern(void* context,
                                                        clothlab_block_pattern* out) {
  const auto& self = *static_cast<const ReferenceSystem*>(context);
  if (out == nullptr || out->struct_size < sizeof(clothlab_block_pattern))
    return CLOTHLAB_ERROR_INVALID_ARGUMENT;
  out->row_count = static_cast<uint32_t>(self.n_);
  out->block_count = static_cast<uint32_t>(self.columns_.size());
  out->row_offsets = self.row_offsets_.data();
  out->columns = self.columns_.data();
  return CLOTHLAB_OK;
}

template <class Real>
clothlab_status ReferenceSystem<Real>::cg_linearise(void* context, double t, const void* x,
                                                    const void* v, double c_x, double c_v) {
  if (x == nullptr) return CLOTHLAB_ERROR_INVALID_ARGUMENT;
  static_cast<ReferenceSystem*>(context)->linearised_ = {t, x, v, c_x, c_v};
  return CLOTHLAB_OK;
}

template <class Real>
clothlab_status ReferenceSystem<Real>::cg_product(void* context, double alpha, double beta,
                                                  const void* z, void* p, void* solution, void* q,
                                                  double* p_dot_q) {
  const Linearisation at = static_cast<const ReferenceSystem*>(context)->linearised_;
  if (p_dot_q == nullptr || q == p || at.x == nullptr) return CLOTHLAB_ERROR_INVALID_ARGUMENT;
  if (z != nullptr) {
    axpy_callback(context, solution, alpha, p);
    const void* const terms[] = {p};
    lincomb_callback(context, p, z, 1, &beta, terms);
  }
  const clothlab_status status =
      jacobian_apply<true>(context, at.t, at.x, at.v, at.c_x, at.c_v, p, q);
  if (status != CLOTHLAB_OK) return status;
  axpy_callback(context, q, 1.0, p);
  *p_dot_q = mass_dot(context, p, q);
  return CLOTHLAB_OK;
}

template <class Real>
clothlab_status ReferenceSystem<Real>::cg_update(void* context, double alpha, const void* q,
                                                 const void* diagonal, const void* off_diagonal,
                                                 void* r, void* z, double* r_dot_r,
                                                 double* r_dot_z) {
  if (r_dot_r == nullptr || r_dot_z == nullptr) return CLOTHLAB_ERROR_INVALID_ARGUMENT;
  const auto& self = *static_cast<const ReferenceSystem*>(context);
  axpy_callback(context, r, -alpha, q);
  const Real* rs = static_cast<const Real*>(r);
  const Real* bd = static_cast<const Real*>(diagonal);
  const Real* bo = static_cast<const Real*>(off_diagonal);
  Real* zs = static_cast<Real*>(z);
  const std::size_t n = self.stride_;
  for (const clothlab_range& range : self.active_)
    for (std::size_t i = range.begin; i < range.end; ++i) {
      const double block[3][3] = {{bd[i], bo[i], bo[n + i]},
                                  {bo[i], bd[n + i], bo[2 * n + i]},
                                  {bo[n + i], bo[2 * n + i], bd[2 * n + i]}};
      for (std::size_t row = 0; row < 3; ++row) {
        double sum = 0;
        for (std::size_t k = 0; k < 3; ++k) sum += block[row][k] * double{rs[k * n + i]};
        zs[row * n + i] = static_cast<Real>(sum);
      }
    }
  *r_dot_r = mass_dot(context, r, r);
  *r_dot_z = mass_dot(context, r, z);
  return CLOTHLAB_OK;
}

template <class Real>
double ReferenceSystem<Real>::dot(void* context, const void* a, const void* b) {
  const auto& self = *static_cast<const ReferenceSystem*>(context);
  double sum = 0;
  for (const clothlab_range& range : self.active_)
    for (std::size_t k = 0; k < 3; ++k)
      for (std::size_t i = range.begin; i < range.end; ++i)
        sum += double{static_cast<const Real*>(a)[k * self.stride_ + i]} *
               double{static_cast<const Real*>(b)[k * self.stride_ + i]};
  return sum;
}

template <class Real>
double ReferenceSystem<Real>::mass_dot(void* context, const void* a, const void* b) {
  const auto& self = *static_cast<const ReferenceSystem*>(context);
  double sum = 0;
  for (const clothlab_range& range : self.active_)
    for (std::size_t k = 0; k < 3; ++k)
      for (std::size_t i = range.begin; i < range.end; ++i)
        sum += double{static_cast<const Real*>(a)[k * self.stride_ + i]} *
               double{static_cast<const Real*>(b)[k * self.stride_ + i]} /
               double{self.inverse_mass_[i]};
  return sum;
}

template <class Real>
double ReferenceSystem<Real>::max_abs(void* context, const void* a) {
  const auto& self = *static_cast<const ReferenceSystem*>(context);
  double worst = 0;
  for (const clothlab_range& range : self.active_)
    for (std::size_t k = 0; k < 3; ++k)
      for (std::size_t i = range.begin; i < range.end; ++i) {
        const double value = std::fabs(double{static_cast<const Real*>(a)[k * self.stride_ + i]});
        if (value > worst || std::isnan(value)) worst = value;
      }
  return worst;
}

template <class Real>
clothlab_status ReferenceSystem<Real>::external(void* context, double, const void* x, void* a) {
  auto& self = *static_cast<ReferenceSystem*>(context);
  const Real* xs = static_cast<const Real*>(x);
  // The air at the system's current velocities, as the engine does (clothlab/ext/air.h).
  const Real* vs = static_cast<const Real*>(self.system_.v);
  for (std::size_t i = 0; i < self.n_; ++i)
    for (std::size_t k = 0; k < 3; ++k) {
      self.x_aos_[3 * i + k] = xs[k * self.stride_ + i];
      self.v_aos_[3 * i + k] = vs[k * self.stride_ + i];
    }
  self.cloth_.external_acceleration(self.x_aos_.data(), self.v_aos_.data(), self.a_aos_.data());
  Real* out = static_cast<Real*>(a);
  bool finite = true;
  for (std::size_t i = 0; i < self.n_; ++i)
    for (std::size_t k = 0; k < 3; ++k) {
      out[k * self.stride_ + i] = self.a_aos_[3 * i + k];
      finite = finite && std::isfinite(out[k * self.stride_ + i]);
    }
  return finite ? CLOTHLAB_OK : CLOTHLAB_ERROR_NUMERICAL;
}

template <class Real>
int32_t ReferenceSystem<Real>::depends_on_position(void* context) {
  return static_cast<const ReferenceSystem*>(context)->wind_ ? 1 : 0;
}

template class ReferenceSystem<float>;
template class ReferenceSystem<double>;

}  // namespace clothlab::reference
