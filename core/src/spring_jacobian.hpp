// Analytic derivatives of the spring accelerations (the host side of
// "clothlab.jacobian/1"): J = c_x da/dx + c_v da/dv of the force eval_acceleration
// computes, F_i = [ks (l - l0) + kd (u . dv)] u per spring with d = x_j - x_i, l = |d|,
// u = d / l, dv = v_j - v_i. Per spring, dF_i = M (du_j - du_i) with
//   M = c_x K + c_v kd u u^T,   K = ks (I - (l0/l)(I - u u^T)) + (kd/l) (u (P dv)^T + (u.dv) P),
// P = I - u u^T (the second term is the damping force's dependence on x); M is the same
// seen from either end. Gravity is constant and wind's x-dependence is left out.
//
// apply runs over the grid rows as the force pipeline does: per row and stencil it computes
// each spring's M (u_j - u_i) once, without forming M (jacobian_row_kernel.hpp), and adds it
// at both ends, straight into the two rows of `out` (a stencil within one row through a
// scratch row and a shifted add), negated at the second end (seen from there d, u, dv and du
// only change sign, which is exact). Each thread owns a block of
// rows of `out` and first runs the two rows above it for their springs into it: no scatter
// between threads, no atomics, and every particle sums its springs in the same order for
// any thread count. The block forms build M per adjacency entry.
// On the spring list (any mesh, or a grid forced onto the general path) the products run by
// gather instead (spring_list_jacobian.cpp): one pass puts each spring's M (u_j - u_i) in its
// slot of SpringLanes, a second sums each particle's slots in a fixed order; the same bits on
// any thread count, no atomics.
// Everything is allocated by the constructor; the calls never allocate.
#pragma once

#include <clothlab/ext/jacobian.h>

#include <clothlab/core/cloth_model.hpp>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

#include "aligned_buffer.hpp"
#include "definite_row_kernel.hpp"
#include "grid.hpp"
#include "jacobian_row_kernel.hpp"
#include "simd_namespace.hpp"
#include "spring_lanes.hpp"

namespace clothlab::detail::inline CLOTHLAB_SIMD_NAMESPACE {

template <class Real>
class SpringJacobian {
 public:
  // damping: whether eval_acceleration applies spring damping when given velocities;
  // spring_list: the products gather over the model's springs instead of sweeping grid rows.
  SpringJacobian(const Scene& scene, const ClothModel& topology, const Real* inverse_mass,
                 std::size_t stride, bool damping, int threads, bool parallel, bool spring_list);

  // Whether the passes run on the thread team (false: on the calling thread alone); the engine
  // sets it per step (TeamGovernor). Results are the same bits either way.
  void set_parallel(bool parallel) { parallel_ = parallel; }

  // out = J u (Real vectors of the system); v == nullptr: no damping terms.
  void apply(const Real* x, const Real* v, double c_x, double c_v, const Real* u, Real* out) const;
  // As apply and diagonal_blocks, with J in Baraff and Witkin's definite form
  // (clothlab/ext/definite_jacobian.h, jacobian_row_kernel.hpp).
  void apply_definite(const Real* x, const Real* v, double c_x, double c_v, const Real* u,
                      Real* out) const;
  // Fixes the definite form D at (x, v) with weights c_x, c_v for product_definite_dot (x and v
  // must keep their values while it is used): on the row kernel's path, each spring's inverse
  // length (fused_cg_product.cpp).
  void linearise_definite(const Real* x, const Real* v, double c_x, double c_v) const;
  // q = u + D u at the linearisation; returns <u, q> = sum of m_i u_i . q_i over the active
  // particles, per grid row then the rows in order (clothlab/ext/cg_step.h). false: no
  // linearisation yet.
  // direction (optional): first solution += alpha u, u = z + beta u on the active particles,
  // row by row inside the product's sweep (fuses_direction()).
  struct Direction {
    double alpha, beta;
    const Real* z;
    Real* solution;
  };
  bool product_definite_dot(Real* u, Real* q, double& dot,
                            const Direction* direction = nullptr) const;
  bool fuses_direction() const { return definite_kernel_; }
  void diagonal_blocks_definite(const Real* x, const Real* v, double c_x, double c_v,
                                double* out) const;
  // out[9 i + 3 r + c] = J_ii(r, c).
  void diagonal_blocks(const Real* x, const Real* v, double c_x, double c_v, double* out) const;
  // values: every block of J in pattern()'s order (9 per block); blocks_definite: of D.
  void blocks(const Real* x, const Real* v, double c_x, double c_v, double* values) const;
  void blocks_definite(const Real* x, const Real* v, double c_x, double c_v, double* values) const;
  clothlab_block_pattern pattern() const;

 private:
  struct Weights {
    double c_x, c_v;
    bool damped;
    bool definite = false;
  };
  void diagonal_blocks(const Real* x, const Real* v, const Weights& w, double* out) const;
  void blocks(const Real* x, const Real* v, const Weights& w, double* values) const;
  // M of spring `spring` (see above); 0 for a zero-length spring.
  void spring_block(const Real* x, const Real* v, uint32_t spring, const Weights& w,
                    double* m) const;
  uint32_t partner(uint32_t i, uint32_t spring) const {
    return topology_.first[spring] == i ? topology_.second[spring] : topology_.first[spring];
  }
  // The springs of one Provot stencil that exert force (all of a stencil share rest, ks, kd).
  struct StencilSprings {
    StencilExtent extent;
    uint32_t row_step;
    int32_t col_step;
    Real rest, ks, kd;
  };
  // Shifted: out = u + J u, and each own row's <u, out> into row_dots_.
  template <JacobianForm Form, bool Shifted = false>
  void apply_form(const Real* x, const Real* v, double c_x, double c_v, const Real* u, Real* out,
                  const Direction* direction = nullptr) const;
  // out's grid rows [begin, end) of the product; p is the thread's scratch row.
  template <JacobianForm Form, bool Shifted>
  void apply_rows(const Real* x, const Real* v, const Weights& w, const Real* u, Real* out,
                  std::size_t begin, std::size_t end, Real* p) const;
  // The fused CG kernel (fused_cg_product.cpp): the shifted definite product's rows
  // [begin, end) by definite_row_kernel.hpp (float with SIMD lanes and all six stencils); scratch:
  // the thread's two rows of shifted ends.
  void definite_rows(Real* u, Real* out, std::size_t begin, std::size_t end, Real* scratch,
                     const Direction* direction) const;
  // Stencil s's plane of inverse spring lengths, rows x cols.
  Real* inverse_length_plane(std::size_t s) const { return inverse_lengths_.data() + s * plane_; }
  // Grid row `row` of the shifted product, its springs summed in out: out = u + inverse mass x
  // out, and the row's <u, out> into row_dots_; scratch: a row's worth of the thread's floats.
  void finish_shifted_row(const Real* u, Real* out, std::size_t row, Real* scratch) const;
  // The spring-list products (spring_list_jacobian.cpp): out = J u (Shifted: u + J u, and each
  // particle chunk's share of <u, out> into row_dots_).
  template <JacobianForm Form, bool Shifted>
  void list_apply(const Real* x, const Real* v, const Weights& w, const Real* u, Real* out) const;
  // Each slot's 1/l at the linearisation, from which the CG products build the definite M.
  void list_linearise(const Real* x) const;
  // Pass 1: slot s = M_s (u_second - u_first), pinned ends' u taken as 0; block(spring, m)
  // gives the M of the slot's spring.
  template <class Block>
  void list_spring_products(const Real* u, Block&& block) const;
  // Pass 2 on particle blocks [begin, end): out_i = inverse mass x the sum of particle i's slots
  // (each signed by its end; the bands' slots from ring where given, a sweep's); Shifted:
  // out = u + that, and returns the blocks' <u, out>_M.
  template <bool Shifted>
  double list_gather_blocks(const Real* u, Real* out, const Real* ring, std::size_t begin,
                            std::size_t end) const;
  // Calls body(i) for every particle, threads over chunks of particles.
  template <class Body>
  void for_particles(Body&& body) const;
  // Calls body(begin, end) for chunks covering [0, count), threads over the chunks.
  template <class Body>
  void for_chunks(std::size_t count, Body&& body) const;

  const ClothModel& topology_;
  bool spring_list_;  // the gather products (no grid rows)
  const Real* inverse_mass_;
  std::size_t stride_;
  std::size_t n_;
  std::size_t rows_, cols_;
  std::vector<StencilSprings> stencils_;
  bool damping_;
  int threads_;
  bool parallel_;  // set_parallel
  // Block CSR pattern: row i's columns, ascending; the slot of each adjacency entry's
  // block and of each diagonal block in it.
  std::vector<uint32_t> row_offsets_, columns_, entry_slot_, diagonal_slot_;
  // The other particle of each adjacency entry, and the slot of the entry's block in its row.
  std::vector<uint32_t> entry_partner_, entry_mirror_slot_;
  // Per thread a scratch row of M (u_j - u_i), components span_ apart, zero margins
  // (apply is not reentrant).
  std::size_t span_;
  mutable AlignedBuffer<Real> product_rows_;
  bool definite_kernel_ = false;           // definite_rows applies
  mutable AlignedBuffer<Real> ends_rows_;  // per thread 2 x 3 rows of span_, for definite_rows
  std::size_t plane_ = 0;                  // rows x cols, rounded up to 16
  mutable AlignedBuffer<Real> inverse_lengths_;  // definite_rows: a plane per stencil
  struct Linearisation {
    const Real *x = nullptr, *v = nullptr;
    double c_x = 0.0, c_v = 0.0;
  };
  mutable Linearisation linearised_;  // x == nullptr: none yet
  AlignedBuffer<Real> mass_;          // 1 / inverse mass, 0 where pinned
  // Per grid row (on the spring list: per particle chunk): its share of <u, out>.
  mutable std::vector<double> row_dots_;
  // Spring list: the slots (laid out as SpringLanes' forces) of pass 1's products, 3 per slot,
  // and list_linearise's 1/l, 1 per slot.
  std::optional<SpringLanes<Real>> spring_lanes_;
  mutable AlignedBuffer<Real> spring_products_;
  mutable AlignedBuffer<Real> spring_rings_;  // per thread (SlotBuffers)
  mutable AlignedBuffer<Real> spring_inverse_length_;
};

}  // namespace clothlab::detail::inline CLOTHLAB_SIMD_NAMESPACE
