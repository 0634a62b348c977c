// Typed C++ views of the host extensions (clothlab/ext/*.h), returned by
// System<Real>::topology(), grid(), jacobian(), definite_jacobian(), cg_step(), reductions(),
// external_forces() and contacts() in sdk.hpp.
// Each wrapper holds the extension's function table and the system's context; a failing
// call throws sdk::Error with the host's status.
#pragma once

#include <clothlab/ext/cg_step.h>
#include <clothlab/ext/contacts.h>
#include <clothlab/ext/definite_jacobian.h>
#include <clothlab/ext/external_forces.h>
#include <clothlab/ext/grid.h>
#include <clothlab/ext/jacobian.h>
#include <clothlab/ext/reductions.h>
#include <clothlab/ext/threads.h>
#include <clothlab/ext/topology.h>

#include <cstdint>
#include <span>

#include "error.hpp"

namespace clothlab::sdk {

// The cloth's springs, triangles, adjacency and colourings (host-owned, fixed while the
// system lives).
class Topology {
 public:
  explicit Topology(const clothlab_topology& raw) : raw_(raw) {}

  uint32_t particle_count() const { return raw_.particle_count; }
  uint32_t spring_count() const { return raw_.spring_count; }
  uint32_t triangle_count() const { return raw_.triangle_count; }
  std::span<const uint32_t> first() const { return {raw_.first, raw_.spring_count}; }
  std::span<const uint32_t> second() const { return {raw_.second, raw_.spring_count}; }
  std::span<const double> rest_length() const { return {raw_.rest_length, raw_.spring_count}; }
  std::span<const double> ks() const { return {raw_.ks, raw_.spring_count}; }
  std::span<const double> kd() const { return {raw_.kd, raw_.spring_count}; }
  std::span<const uint8_t> family() const { return {raw_.family, raw_.spring_count}; }
  std::span<const uint32_t> triangles() const { return {raw_.triangles, 3u * raw_.triangle_count}; }
  // The springs touching particle i, ascending.
  std::span<const uint32_t> springs_of(uint32_t particle) const {
    const uint32_t begin = raw_.adjacency_offsets[particle];
    return {raw_.adjacent_springs + begin, raw_.adjacency_offsets[particle + 1] - begin};
  }
  uint32_t spring_color_count() const { return raw_.spring_color_count; }
  // The springs of one colour: no two share a particle.
  std::span<const uint32_t> spring_color(uint32_t color) const {
    const uint32_t begin = raw_.spring_color_offsets[color];
    return {raw_.spring_color_members + begin, raw_.spring_color_offsets[color + 1] - begin};
  }
  uint32_t particle_color_count() const { return raw_.particle_color_count; }
  // The particles of one colour: no spring joins two of them.
  std::span<const uint32_t> particle_color(uint32_t color) const {
    const uint32_t begin = raw_.particle_color_offsets[color];
    return {raw_.particle_color_members + begin, raw_.particle_color_offsets[color + 1] - begin};
  }
  const clothlab_topology& raw() const { return raw_; }

 private:
  clothlab_topology raw_;
};

// The regular grid the cloth is laid out on (host-owned, fixed while the system lives):
// rows x cols particles, particle r * cols + c.
class Grid {
 public:
  explicit Grid(const clothlab_grid& raw) : raw_(raw) {}

  uint32_t rows() const { return raw_.rows; }
  uint32_t cols() const { return raw_.cols; }
  double column_spacing() const { return raw_.column_spacing; }
  double row_spacing() const { return raw_.row_spacing; }
  // Topology colour c's stencil and parity at [c]; empty when the colours are no stencils.
  std::span<const clothlab_grid_color> spring_colors() const {
    if (raw_.spring_colors == nullptr) return {};
    return {raw_.spring_colors, raw_.spring_color_count};
  }
  const clothlab_grid& raw() const { return raw_; }

 private:
  clothlab_grid raw_;
};

// J = c_x (da/dx) + c_v (da/dv) at a state (x, v); v = nullptr leaves out damping.
template <class Real>
class Jacobian {
 public:
  Jacobian(const clothlab_jacobian_extension& table, void* context)
      : table_(&table), context_(context) {}

  // Readies the calls below; from `prepare` only (may allocate).
  void reserve() const { check(table_->reserve(context_), "jacobian reserve failed"); }
  // out = J u on active particles (0 on pinned ones); out must not alias u, x or v.
  void apply(double t, const Real* x, const Real* v, double c_x, double c_v, const Real* u,
             Real* out) const {
    check(table_->apply(context_, t, x, v, c_x, c_v, u, out), "jacobian apply failed");
  }
  // out[9 i + 3 r + c] = J_ii(r, c), 9 n doubles.
  void diagonal_blocks(double t, const Real* x, const Real* v, double c_x, double c_v,
                       double* out) const {
    check(table_->diagonal_blocks(context_, t, x, v, c_x, c_v, out),
          "jacobian diagonal_blocks failed");
  }
  // The fixed block-CSR pattern of J.
  clothlab_block_pattern pattern() const {
    clothlab_block_pattern out{};
    out.struct_size = sizeof out;
    check(table_->pattern(context_, &out), "jacobian pattern failed");
    return out;
  }
  // All blocks in the pattern's order, 9 block_count doubles.
  void blocks(double t, const Real* x, const Real* v, double c_x, double c_v,
              double* values) const {
    check(table_->blocks(context_, t, x, v, c_x, c_v, values), "jacobian blocks failed");
  }

 private:
  const clothlab_jacobian_extension* table_;
  void* context_;
};

// D = c_x K + c_v (da/dv), Baraff and Witkin's definite form of the Jacobian (see
// clothlab/ext/definite_jacobian.h); readied by Jacobian::reserve. block_table: the host's
// clothlab.definite-jacobian/2, or null where it offers /1 alone.
template <class Real>
class DefiniteJacobian {
 public:
  DefiniteJacobian(const clothlab_definite_jacobian_extension& table, void* context,
                   const clothlab_definite_jacobian_2_extension* block_table = nullptr)
      : table_(&table), block_table_(block_table), context_(context) {}

  // out = D u on active particles (0 on pinned ones); out must not alias u, x or v.
  void apply(double t, const Real* x, const Real* v, double c_x, double c_v, const Real* u,
             Real* out) const {
    check(table_->apply(context_, t, x, v, c_x, c_v, u, out), "definite jacobian apply failed");
  }
  // out[9 i + 3 r + c] = D_ii(r, c), 9 n doubles.
  void diagonal_blocks(double t, const Real* x, const Real* v, double c_x, double c_v,
                       double* out) const {
    check(table_->diagonal_blocks(context_, t, x, v, c_x, c_v, out),
          "definite jacobian diagonal_blocks failed");
  }
  // Whether the host offers every block at once (clothlab.definite-jacobian/2).
  bool has_blocks() const { return block_table_ != nullptr; }
  // Every block of D in the order of Jacobian::pattern, 9 block_count doubles; has_blocks only.
  void blocks(double t, const Real* x, const Real* v, double c_x, double c_v,
              double* values) const {
    check(block_table_->blocks(context_, t, x, v, c_x, c_v, values),
          "definite jacobian blocks failed");
  }

 private:
  const clothlab_definite_jacobian_extension* table_;
  const clothlab_definite_jacobian_2_extension* block_table_;
  void* context_;
};

// The two fused sweeps of a block-Jacobi PCG iteration on A = I + D, D the definite Jacobian,
// in the mass inner product (clothlab/ext/cg_step.h); readied by Jacobian::reserve.
template <class Real>
class CgStep {
 public:
  CgStep(const clothlab_cg_step_extension& table, void* context)
      : table_(&table), context_(context) {}

  // Fixes A at (x, v) with weights c_x, c_v for the products that follow; x and v must keep
  // their values meanwhile.
  void linearise(double t, const Real* x, const Real* v, double c_x, double c_v) const {
    check(table_->linearise(context_, t, x, v, c_x, c_v), "cg-step linearise failed");
  }
  // q = A p; returns <p, q>.
  double product(const Real* p, Real* q) const {
    double p_dot_q = 0.0;
    check(table_->product(context_, 0.0, 0.0, nullptr, const_cast<Real*>(p), nullptr, q, &p_dot_q),
          "cg-step product failed");
    return p_dot_q;
  }
  // solution += alpha p, p = z + beta p, then q = A p; returns <p, q>.
  double product(double alpha, double beta, const Real* z, Real* p, Real* solution, Real* q) const {
    double p_dot_q = 0.0;
    check(table_->product(context_, alpha, beta, z, p, solution, q, &p_dot_q),
          "cg-step product failed");
    return p_dot_q;
  }
  struct Residual {
    double r_dot_r, r_dot_z;
  };
  // r -= alpha q, z = B r, B's symmetric blocks as (B_00, B_11, B_22) in diagonal and
  // (B_01, B_02, B_12) in off_diagonal; returns <r, r> and <r, z>.
  Residual update(double alpha, const Real* q, const Real* diagonal, const Real* off_diagonal,
                  Real* r, Real* z) const {
    Residual out{};
    check(table_->update(context_, alpha, q, diagonal, off_diagonal, r, z, &out.r_dot_r,
                         &out.r_dot_z),
          "cg-step update failed");
    return out;
  }

 private:
  const clothlab_cg_step_extension* table_;
  void* context_;
};

// Deterministic reductions over the active particles (double, fixed summation order).
template <class Real>
class Reductions {
 public:
  Reductions(const clothlab_reductions_extension& table, void* context)
      : table_(&table), context_(context) {}

  double dot(const Real* a, const Real* b) const { return table_->dot(context_, a, b); }
  double mass_dot(const Real* a, const Real* b) const { return table_->mass_dot(context_, a, b); }
  double max_abs(const Real* a) const { return table_->max_abs(context_, a); }

 private:
  const clothlab_reductions_extension* table_;
  void* context_;
};

// Gravity and wind alone (no springs).
template <class Real>
class ExternalForces {
 public:
  // rows_table: the host's clothlab.external-forces/2, nullptr where it has /1 alone.
  ExternalForces(const clothlab_external_forces_extension& table, void* context,
                 const clothlab_external_forces_2_extension* rows_table = nullptr)
      : table_(&table), context_(context), rows_table_(rows_table) {}

  void acceleration(double t, const Real* x, Real* a) const {
    check(table_->acceleration(context_, t, x, a), "external acceleration failed");
  }
  // False when the external acceleration is constant (no wind): one evaluation per step.
  bool depends_on_position() const { return table_->depends_on_position(context_) != 0; }
  // Whether the host computes a range of grid rows (acceleration_rows).
  bool has_rows() const { return rows_table_ != nullptr; }
  // Whether the accelerations read the system's velocities too (air); true without /2.
  bool depends_on_velocity() const {
    return rows_table_ == nullptr || rows_table_->depends_on_velocity(context_) != 0;
  }
  // a on grid rows [begin, end), the bits `acceleration` writes there; has_rows only. Returns
  // the status instead of throwing: it runs on a plugin's worker threads (see the header for
  // `slot`).
  clothlab_status acceleration_rows(double t, const Real* x, Real* a, uint32_t begin, uint32_t end,
                                    uint32_t slot) const noexcept {
    return rows_table_->acceleration_rows(context_, t, x, a, begin, end, slot);
  }

 private:
  const clothlab_external_forces_extension* table_;
  void* context_;
  const clothlab_external_forces_2_extension* rows_table_;
};

// Keeps the cloth out of the scene's colliders (clothlab/ext/contacts.h): call after each step
// or substep, and declare CLOTHLAB_TRAIT_RESOLVES_CONTACTS.
template <class Real>
class Contacts {
 public:
  Contacts(const clothlab_contacts_extension& table, void* context)
      : table_(&table), context_(context) {}

  void resolve(double t, Real* x, Real* v) const {
    check(table_->resolve(context_, t, x, v), "contact resolution failed");
  }

 private:
  const clothlab_contacts_extension* table_;
  void* context_;
};

}  // namespace clothlab::sdk
