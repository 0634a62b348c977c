// A small spring network as a MockSystem that offers the host extensions implicit and
// projective integrators need: topology, jacobian and its definite form (matrix-free
// products and diagonal blocks), reductions and external forces, written here from the same force
// law as its eval_acceleration (Hooke + damping along each spring, gravity), so the plugins can
// be tested against analytic solutions without the core. A free particle's acceleration is its
// spring force over its mass (1 kg unless the test calls MockSystem::set_mass) plus gravity, so
// M J is symmetric with any masses, as the host contract asks.
#pragma once

#include <clothlab/ext/attachment_targets.h>
#include <clothlab/ext/cg_step.h>
#include <clothlab/ext/contacts.h>
#include <clothlab/ext/definite_jacobian.h>
#include <clothlab/ext/external_forces.h>
#include <clothlab/ext/grid.h>
#include <clothlab/ext/jacobian.h>
#include <clothlab/ext/reductions.h>
#include <clothlab/ext/threads.h>
#include <clothlab/ext/topology.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <utility>
#include <vector>

#include "mock_system.hpp"

namespace clothlab::test {

struct TestSpring {
  uint32_t first, second;  // first < second
  double rest_length, ks, kd;
};

// The springs of a rows x cols Provot net `spacing` apart in row-major order: structural and
// shear springs of stiffness ks, flexion springs two apart of stiffness ks_flexion, all damped
// by kd.
inline std::vector<TestSpring> provot_net_springs(uint32_t rows, uint32_t cols, double spacing,
                                                  double ks, double ks_flexion, double kd) {
  std::vector<TestSpring> out;
  const int stencils[6][2] = {{0, 1}, {1, 0}, {1, 1}, {1, -1}, {0, 2}, {2, 0}};
  for (uint32_t r = 0; r < rows; ++r)
    for (uint32_t c = 0; c < cols; ++c)
      for (const auto& s : stencils) {
        const int r2 = static_cast<int>(r) + s[0], c2 = static_cast<int>(c) + s[1];
        if (r2 >= static_cast<int>(rows) || c2 < 0 || c2 >= static_cast<int>(cols)) continue;
        const uint32_t i = r * cols + c,
                       j = static_cast<uint32_t>(r2) * cols + static_cast<uint32_t>(c2);
        const bool flexion = s[0] == 2 || s[1] == 2;
        out.push_back({std::min(i, j), std::max(i, j), spacing * std::hypot(s[0], s[1]),
                       flexion ? ks_flexion : ks, kd});
      }
  return out;
}

// The first particle of every row: a net pinned along its left column.
inline std::vector<uint32_t> left_column(uint32_t rows, uint32_t cols) {
  std::vector<uint32_t> pinned;
  for (uint32_t r = 0; r < rows; ++r) pinned.push_back(r * cols);
  return pinned;
}

template <class Real>
class SpringHost {
 public:
  SpringHost(uint32_t particle_count, std::vector<uint32_t> pinned, std::vector<TestSpring> springs,
             Vec3 gravity)
      : springs_(std::move(springs)),
        gravity_(gravity),
        system_(particle_count, std::move(pinned),
                [this](double, uint32_t i, const Real* x, const Real* v, uint32_t stride) {
                  return acceleration_of(i, x, v, stride);
                }) {
    system_.extension_data = this;
    system_.extensions = [this](const char* id) -> const void* {
      if (std::strcmp(id, CLOTHLAB_EXT_TOPOLOGY) == 0) return &topology_table;
      if (std::strcmp(id, CLOTHLAB_EXT_GRID) == 0) return grid_.struct_size ? &grid_table : nullptr;
      if (std::strcmp(id, CLOTHLAB_EXT_JACOBIAN) == 0) return &jacobian_table;
      if (std::strcmp(id, CLOTHLAB_EXT_DEFINITE_JACOBIAN) == 0) return &definite_jacobian_table;
      if (std::strcmp(id, CLOTHLAB_EXT_REDUCTIONS) == 0) return &reductions_table;
      if (std::strcmp(id, CLOTHLAB_EXT_EXTERNAL_FORCES) == 0) return &external_table;
      if (std::strcmp(id, CLOTHLAB_EXT_EXTERNAL_FORCES_2) == 0)
        return grid_.struct_size && rows_call_ ? &external_2_table : nullptr;
      if (std::strcmp(id, CLOTHLAB_EXT_THREADS) == 0) return threads_ ? &threads_table : nullptr;
      return nullptr;
    };
    build_topology(particle_count);
  }
  SpringHost(const SpringHost&) = delete;
  SpringHost& operator=(const SpringHost&) = delete;

  MockSystem<Real>& system() { return system_; }
  // The host extensions it never offers (clothlab/core/extension_registry.hpp): the tests it
  // serves need no fused CG sweeps, colliders or attachments, and no block table (its multigrid
  // tests probe the product). The grid, the external forces' rows call and the thread count
  // are offered once set_grid and set_threads have been called.
  static constexpr const char* kDeclinedExtensions[] = {CLOTHLAB_EXT_CG_STEP, CLOTHLAB_EXT_CONTACTS,
                                                        CLOTHLAB_EXT_ATTACHMENT_TARGETS,
                                                        CLOTHLAB_EXT_DEFINITE_JACOBIAN_2};
  int jacobian_products = 0;  // of either form

  // Replaces the trivial spring colouring (one spring per colour) with `colors`, spring
  // indices per colour; the test vouches that no two springs of a colour share a particle.
  void set_spring_colors(const std::vector<std::vector<uint32_t>>& colors) {
    spring_color_offsets_.assign(1, 0);
    spring_colors_.clear();
    for (const std::vector<uint32_t>& color : colors) {
      spring_colors_.insert(spring_colors_.end(), color.begin(), color.end());
      spring_color_offsets_.push_back(static_cast<uint32_t>(spring_colors_.size()));
    }
  }

  // Replaces the trivial particle colouring (one particle per colour) with `colors`, particle
  // indices per colour; the test vouches that no spring joins two particles of a colour.
  void set_particle_colors(const std::vector<std::vector<uint32_t>>& colors) {
    particle_color_offsets_.assign(1, 0);
    particle_colors_.clear();
    for (const std::vector<uint32_t>& color : colors) {
      particle_colors_.insert(particle_colors_.end(), color.begin(), color.end());
      particle_color_offsets_.push_back(static_cast<uint32_t>(particle_colors_.size()));
    }
  }

  // Offers clothlab.grid/1: the particles are a rows x cols grid `spacing` apart and colour c
  // of the topology is the stencil colors[c]; the test vouches for both.
  void set_grid(uint32_t rows, uint32_t cols, double spacing,
                std::vector<clothlab_grid_color> colors) {
    grid_colors_ = std::move(colors);
    grid_ = {sizeof(clothlab_grid),
             rows,
             cols,
             static_cast<uint32_t>(grid_colors_.size()),
             spacing,
             spacing,
             grid_colors_.data()};
  }

  // Offers clothlab.threads/1: the host lets the system's work use `count` threads.
  void set_threads(uint32_t count) { threads_ = count; }

  // Adds an external field that depends on x, `strength` (x_above + x_below - 2 x_i) from the
  // particles one grid row apart (the particle itself past an edge); `rows_call` false hides
  // clothlab.external-forces/2 (offered with the grid), so that /1's call alone gives it.
  void set_position_field(double strength, bool rows_call) {
    field_ = strength;
    rows_call_ = rows_call;
  }

  // J u with J = c_x da/dx + c_v da/dv at (x, v), on all particles (pinned rows 0);
  // definite: clothlab.definite-jacobian/1's form.
  void jacobian_product(const Real* x, const Real* v, double c_x, double c_v, const Real* u,
                        Real* out, bool definite = false) const {
    const uint32_t stride = system_.stride();
    std::vector<double> sum(3 * size_t{stride}, 0.0);
    for (const TestSpring& s : springs_) {
      const Block b = spring_block(s, x, v, c_x, c_v, definite);
      for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) {
          const double du = value(u, s.first, c) - value(u, s.second, c);
          sum[r * stride + s.first] += b[3 * r + c] * du;
          sum[r * stride + s.second] -= b[3 * r + c] * du;
        }
    }
    for (size_t j = 0; j < sum.size(); ++j) out[j] = 0;
    for_active([&](uint32_t i) {
      for (int k = 0; k < 3; ++k)
        out[k * stride + i] = static_cast<Real>(mass_inverse(i) * sum[k * stride + i]);
    });
  }

 private:
  using Block = std::array<double, 9>;

  static SpringHost& self(void* context) {
    return *static_cast<SpringHost*>(static_cast<MockSystem<Real>*>(context)->extension_data);
  }

  double value(const Real* vector, uint32_t i, int k) const {
    return vector[k * system_.stride() + i];
  }
  bool active(uint32_t i) const { return mass_inverse(i) != 0; }
  double mass_inverse(uint32_t i) const {
    return static_cast<const Real*>(system_.raw().inverse_mass)[i];
  }
  template <class Body>
  void for_active(Body&& body) const {
    for (uint32_t r = 0; r < system_.raw().active_count; ++r)
      for (uint32_t i = system_.raw().active[r].begin; i < system_.raw().active[r].end; ++i)
        body(i);
  }

  // The external acceleration of an active particle: gravity and the field.
  Vec3 external_of(uint32_t i, const Real* x) const {
    Vec3 a = gravity_;
    if (field_ == 0.0) return a;
    const uint32_t cols = grid_.cols, n = system_.raw().particle_count;
    const uint32_t above = i >= cols ? i - cols : i, below = i + cols < n ? i + cols : i;
    for (int k = 0; k < 3; ++k)
      a[k] += field_ * (value(x, above, k) + value(x, below, k) - 2 * value(x, i, k));
    return a;
  }

  Vec3 acceleration_of(uint32_t i, const Real* x, const Real* v, uint32_t stride) const {
    (void)stride;
    Vec3 f{};
    for (const TestSpring& s : springs_) {
      if (s.first != i && s.second != i) continue;
      const uint32_t other = s.first == i ? s.second : s.first;
      Vec3 d{}, w{};
      for (int k = 0; k < 3; ++k) {
        d[k] = value(x, i, k) - value(x, other, k);
        w[k] = v == nullptr ? 0.0 : value(v, i, k) - value(v, other, k);
      }
      const double length = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
      const double along = (d[0] * w[0] + d[1] * w[1] + d[2] * w[2]) / length;
      for (int k = 0; k < 3; ++k)
        f[k] += -s.ks * (length - s.rest_length) * d[k] / length - s.kd * along * d[k] / length;
    }
    Vec3 a = external_of(i, x);
    for (int k = 0; k < 3; ++k) a[k] += mass_inverse(i) * f[k];
    return a;
  }

  // d f_first / d x_first (times c_x) + d f_first / d v_first (times c_v), the force's (the
  // callers divide by the mass): Hooke
  // -ks ((1 - l0/l) I + (l0/l) n n^T), damping -kd n n^T in v and, in x, the turning of n:
  // -kd (n w^T + (n.w) I) (I - n n^T) / l, w = v_first - v_second. Definite: Hooke
  // -ks (max(0, 1 - l0/l) (I - n n^T) + n n^T) and no turning term.
  Block spring_block(const TestSpring& s, const Real* x, const Real* v, double c_x, double c_v,
                     bool definite = false) const {
    Vec3 d{}, w{};
    for (int k = 0; k < 3; ++k) {
      d[k] = value(x, s.first, k) - value(x, s.second, k);
      w[k] = v == nullptr ? 0.0 : value(v, s.first, k) - value(v, s.second, k);
    }
    const double l = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    const Vec3 n{d[0] / l, d[1] / l, d[2] / l};
    const double nw = n[0] * w[0] + n[1] * w[1] + n[2] * w[2];
    const double kd = v == nullptr ? 0.0 : s.kd;
    Block b{};
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) {
        const double identity = r == c ? 1.0 : 0.0;
        const double hooke =
            definite
                ? -s.ks * (std::max(0.0, 1 - s.rest_length / l) * (identity - n[r] * n[c]) +
                           n[r] * n[c])
                : -s.ks * ((1 - s.rest_length / l) * identity + s.rest_length / l * n[r] * n[c]);
        double turning = 0.0;
        for (int m = 0; m < 3 && !definite; ++m)
          turning +=
              (n[r] * w[m] + nw * (r == m ? 1.0 : 0.0)) * ((m == c ? 1.0 : 0.0) - n[m] * n[c]) / l;
        b[3 * r + c] = c_x * (hooke - kd * turning) + c_v * (-kd * n[r] * n[c]);
      }
    return b;
  }

  void build_topology(uint32_t n) {
    for (const TestSpring& s : springs_) {
      first_.push_back(s.first);
      second_.push_back(s.second);
      rest_.push_back(s.rest_length);
      ks_.push_back(s.ks);
      kd_.push_back(s.kd);
      family_.push_back(CLOTHLAB_SPRING_STRUCTURAL);
    }
    offsets_.assign(n + 1, 0);
    for (const TestSpring& s : springs_) ++offsets_[s.first + 1], ++offsets_[s.second + 1];
    for (uint32_t i = 0; i < n; ++i) offsets_[i + 1] += offsets_[i];
    adjacent_.resize(offsets_[n]);
    std::vector<uint32_t> fill(offsets_.begin(), offsets_.end() - 1);
    for (uint32_t k = 0; k < springs_.size(); ++k) {
      adjacent_[fill[springs_[k].first]++] = k;
      adjacent_[fill[springs_[k].second]++] = k;
    }
    // Trivial colourings: one spring, one particle per colour.
    for (uint32_t k = 0; k <= springs_.size(); ++k) spring_color_offsets_.push_back(k);
    for (uint32_t k = 0; k < springs_.size(); ++k) spring_colors_.push_back(k);
    for (uint32_t i = 0; i <= n; ++i) particle_color_offsets_.push_back(i);
    for (uint32_t i = 0; i < n; ++i) particle_colors_.push_back(i);
  }

  static clothlab_status get_topology(void* context, clothlab_topology* out) {
    const SpringHost& s = self(context);
    const auto springs = static_cast<uint32_t>(s.springs_.size());
    const uint32_t n = s.system_.raw().particle_count;
    *out = {sizeof(clothlab_topology),
            n,
            springs,
            0,
            s.first_.data(),
            s.second_.data(),
            s.rest_.data(),
            s.ks_.data(),
            s.kd_.data(),
            s.family_.data(),
            nullptr,
            s.offsets_.data(),
            s.adjacent_.data(),
            static_cast<uint32_t>(s.spring_color_offsets_.size() - 1),
            0,
            s.spring_color_offsets_.data(),
            s.spring_colors_.data(),
            static_cast<uint32_t>(s.particle_color_offsets_.size() - 1),
            0,
            s.particle_color_offsets_.data(),
            s.particle_colors_.data()};
    return CLOTHLAB_OK;
  }

  static clothlab_status get_grid(void* context, clothlab_grid* out) {
    *out = self(context).grid_;
    return CLOTHLAB_OK;
  }

  static clothlab_status reserve(void*) { return CLOTHLAB_OK; }
  template <bool Definite>
  static clothlab_status apply(void* context, double, const void* x, const void* v, double c_x,
                               double c_v, const void* u, void* out) {
    SpringHost& s = self(context);
    ++s.jacobian_products;
    s.jacobian_product(static_cast<const Real*>(x), static_cast<const Real*>(v), c_x, c_v,
                       static_cast<const Real*>(u), static_cast<Real*>(out), Definite);
    return CLOTHLAB_OK;
  }
  template <bool Definite>
  static clothlab_status diagonal_blocks(void* context, double, const void* x, const void* v,
                                         double c_x, double c_v, double* out) {
    const SpringHost& s = self(context);
    const uint32_t n = s.system_.raw().particle_count;
    std::fill(out, out + 9 * size_t{n}, 0.0);
    for (const TestSpring& spring : s.springs_) {
      const Block b = s.spring_block(spring, static_cast<const Real*>(x),
                                     static_cast<const Real*>(v), c_x, c_v, Definite);
      for (uint32_t end : {spring.first, spring.second})
        if (s.active(end))
          for (int k = 0; k < 9; ++k) out[9 * size_t{end} + k] += s.mass_inverse(end) * b[k];
    }
    return CLOTHLAB_OK;
  }
  static clothlab_status no_pattern(void*, clothlab_block_pattern*) {
    return CLOTHLAB_ERROR_UNSUPPORTED;
  }
  static clothlab_status no_blocks(void*, double, const void*, const void*, double, double,
                                   double*) {
    return CLOTHLAB_ERROR_UNSUPPORTED;
  }

  static double dot(void* context, const void* a, const void* b) {
    return self(context).weighted_dot(a, b, false);
  }
  static double mass_dot(void* context, const void* a, const void* b) {
    return self(context).weighted_dot(a, b, true);
  }
  double weighted_dot(const void* a, const void* b, bool by_mass) const {
    double sum = 0;
    for_active([&](uint32_t i) {
      const double weight = by_mass ? 1.0 / mass_inverse(i) : 1.0;
      for (int k = 0; k < 3; ++k)
        sum += weight * value(static_cast<const Real*>(a), i, k) *
               value(static_cast<const Real*>(b), i, k);
    });
    return sum;
  }
  static double max_abs(void* context, const void* a) {
    const SpringHost& s = self(context);
    double largest = 0;
    s.for_active([&](uint32_t i) {
      for (int k = 0; k < 3; ++k)
        largest = std::max(largest, std::abs(s.value(static_cast<const Real*>(a), i, k)));
    });
    return largest;
  }

  static clothlab_status external_acceleration(void* context, double, const void* x, void* a) {
    const SpringHost& s = self(context);
    return external_rows(context, 0.0, x, a, 0, s.grid_.struct_size ? s.grid_.rows : 1, 0);
  }
  // Rows [begin, end) of the grid (or, without one, all particles as row 0).
  static clothlab_status external_rows(void* context, double, const void* x, void* a,
                                       uint32_t begin, uint32_t end, uint32_t slot) {
    const SpringHost& s = self(context);
    const uint32_t n = s.system_.raw().particle_count;
    const uint32_t cols = s.grid_.struct_size ? s.grid_.cols : n;
    if (end * cols > n || begin > end || (s.threads_ != 0 && slot >= s.threads_))
      return CLOTHLAB_ERROR_INVALID_ARGUMENT;
    Real* out = static_cast<Real*>(a);
    const uint32_t stride = s.system_.stride();
    for (int k = 0; k < 3; ++k)
      std::fill(out + k * size_t{stride} + begin * cols, out + k * size_t{stride} + end * cols,
                Real(0));
    s.for_active([&](uint32_t i) {
      if (i < begin * cols || i >= end * cols) return;
      const Vec3 value = s.external_of(i, static_cast<const Real*>(x));
      for (int k = 0; k < 3; ++k) out[k * stride + i] = static_cast<Real>(value[k]);
    });
    return CLOTHLAB_OK;
  }
  static int32_t depends_on_position(void* context) { return self(context).field_ != 0.0; }
  static int32_t no_air(void*) { return 0; }

  static constexpr clothlab_topology_extension topology_table{&get_topology};
  static constexpr clothlab_grid_extension grid_table{&get_grid};
  static uint32_t threads_count(void* context) { return self(context).threads_; }
  static constexpr clothlab_threads_extension threads_table{&threads_count};
  static constexpr clothlab_jacobian_extension jacobian_table{
      &reserve, &apply<false>, &diagonal_blocks<false>, &no_pattern, &no_blocks};
  static constexpr clothlab_definite_jacobian_extension definite_jacobian_table{
      &apply<true>, &diagonal_blocks<true>};
  static constexpr clothlab_reductions_extension reductions_table{&dot, &mass_dot, &max_abs};
  static constexpr clothlab_external_forces_extension external_table{&external_acceleration,
                                                                     &depends_on_position};
  static constexpr clothlab_external_forces_2_extension external_2_table{
      &external_acceleration, &depends_on_position, &external_rows, &no_air};

  std::vector<TestSpring> springs_;
  Vec3 gravity_;
  std::vector<uint32_t> first_, second_, offsets_, adjacent_;
  std::vector<uint32_t> spring_color_offsets_, spring_colors_, particle_color_offsets_,
      particle_colors_;
  std::vector<double> rest_, ks_, kd_;
  std::vector<uint8_t> family_;
  clothlab_grid grid_{};  // struct_size 0: no grid offered
  uint32_t threads_ = 0;  // 0: clothlab.threads/1 not offered
  double field_ = 0.0;    // set_position_field
  bool rows_call_ = true;
  std::vector<clothlab_grid_color> grid_colors_;
  MockSystem<Real> system_;
};

}  // namespace clothlab::test
