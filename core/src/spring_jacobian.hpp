// Analytic derivatives of the spring accelerations (the host side of
// "clothlab.jacobian/1"): J = c_x da/dx + c_v da/dv of the force eval_acceleration
// computes, F_i = [ks (l - l0) + kd (u . dv)] u per spring with d = x_j - x_i, l = |d|,
// u = d / l, dv = v_j - v_i. Per spring, dF_i = M (du_j - du_i) with
//   M = c_x K + c_v kd u u^T,   K = ks (I - (l0/l)(I - u u^T)) + (kd/l) (u (P dv)^T + (u.dv) P),
// P = I - u u^T (the second term is the damping force's dependence on x); M is the same
// seen from either end. Gravity is constant and wind's x-dependence is left out.
//
// apply computes each spring's M (u_j - u_i) once, from the spring's own orientation and
// without forming M, in a pass over the springs into scratch; each particle then gathers it
// over its springs (CSR adjacency), negated at the spring's second end (seen from there d, u,
// dv and du only change sign, which is exact). The block forms build M per adjacency entry.
// No scatter, no atomics, threads split the springs and then the particles: results do not
// depend on the thread count.
// Everything is allocated by the constructor; the calls never allocate.
#pragma once

#include <clothlab/ext/jacobian.h>

#include <cstddef>
#include <cstdint>
#include <vector>

#include "grid_topology.hpp"

namespace clothlab::detail {

template <class Real>
class SpringJacobian {
 public:
  // damping: whether eval_acceleration applies spring damping when given velocities.
  SpringJacobian(const GridTopology& topology, const Real* inverse_mass, std::size_t stride,
                 bool damping, int threads, bool parallel);

  // out = J u (Real vectors of the system); v == nullptr: no damping terms.
  void apply(const Real* x, const Real* v, double c_x, double c_v, const Real* u, Real* out) const;
  // out[9 i + 3 r + c] = J_ii(r, c).
  void diagonal_blocks(const Real* x, const Real* v, double c_x, double c_v, double* out) const;
  void blocks(const Real* x, const Real* v, double c_x, double c_v, double* values) const;
  clothlab_block_pattern pattern() const;

 private:
  struct Weights {
    double c_x, c_v;
    bool damped;
  };
  // M of spring `spring` (see above); 0 for a zero-length spring.
  void spring_block(const Real* x, const Real* v, uint32_t spring, const Weights& w,
                    double* m) const;
  uint32_t partner(uint32_t i, uint32_t spring) const {
    return topology_.first[spring] == i ? topology_.second[spring] : topology_.first[spring];
  }
  // Springs run.spring + k, k < run.count, join run.first + k to run.second + k: contiguous
  // loads in the spring pass instead of gathers.
  struct SpringRun {
    uint32_t spring, count, first, second;
  };
  // The products M (u_j - u_i) of the run's springs into spring_products_.
  template <bool Damped>
  void spring_products(const Real* x, const Real* v, const Real* u, const Weights& w,
                       const SpringRun& run) const;
  // Calls body(i) for every particle, threads over chunks of particles.
  template <class Body>
  void for_particles(Body&& body) const;
  // Calls body(begin, end) for chunks covering [0, count), threads over the chunks.
  template <class Body>
  void for_chunks(std::size_t count, Body&& body) const;

  const GridTopology& topology_;
  const Real* inverse_mass_;
  std::size_t stride_;
  std::size_t n_;
  bool damping_;
  int threads_;
  bool parallel_;
  // Block CSR pattern: row i's columns, ascending; the slot of each adjacency entry's
  // block and of each diagonal block in it.
  std::vector<uint32_t> row_offsets_, columns_, entry_slot_, diagonal_slot_;
  // The other particle of each adjacency entry.
  std::vector<uint32_t> entry_partner_;
  // The springs cut into runs of at most one work item each.
  std::vector<SpringRun> runs_;
  // apply's M (u_second - u_first), component-major (scratch; apply is not reentrant).
  mutable std::vector<double> spring_products_;
};

}  // namespace clothlab::detail
