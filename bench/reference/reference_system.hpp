// The reference forces behind a clothlab_system, so any integrator plugin can run on the
// seed-style baseline: the in-run comparison of issue 4. Vectors are SoA as the ABI
// requires; each evaluation converts to and from the reference's particle-major arrays
// (preallocated) and the vector helpers are plain single-threaded loops.
#pragma once

#include <clothlab/ext/attachment_targets.h>
#include <clothlab/ext/contacts.h>
#include <clothlab/ext/definite_jacobian.h>
#include <clothlab/ext/external_forces.h>
#include <clothlab/ext/grid.h>
#include <clothlab/ext/jacobian.h>
#include <clothlab/ext/threads.h>
#include <clothlab/ext/topology.h>

#include <clothlab/core/cloth.hpp>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <memory>
#include <vector>

#include "reference_forces.hpp"

namespace clothlab::reference {

template <class Real>
class ReferenceSystem {
 public:
  ReferenceSystem(const Scene& scene, bool velocity_forces);
  ReferenceSystem(const ReferenceSystem&) = delete;
  ReferenceSystem& operator=(const ReferenceSystem&) = delete;

  const clothlab_system& system() const { return system_; }
  // The host extensions it does not offer (clothlab/core/extension_registry.hpp): its loops
  // are serial, its scenes have neither colliders nor attachments, and its implicit
  // integrators assemble no multigrid from a block table (they probe the product).
  static constexpr const char* kDeclinedExtensions[] = {
      CLOTHLAB_EXT_THREADS, CLOTHLAB_EXT_CONTACTS, CLOTHLAB_EXT_ATTACHMENT_TARGETS,
      CLOTHLAB_EXT_DEFINITE_JACOBIAN_2, CLOTHLAB_EXT_EXTERNAL_FORCES_2};
  uint64_t force_evals() const { return force_evals_; }
  double force_seconds() const { return force_seconds_; }  // wall time in eval_acceleration
  // Positions, particle-major: out[3 * i + k].
  void positions(std::vector<double>& out) const;

 private:
  struct Free {
    void operator()(Real* p) const { std::free(p); }
  };
  using Vector = std::unique_ptr<Real[], Free>;

  Vector make_vector() const;
  // Element (i, k) of a state combination; pinned particles take the base value.
  Real combined(const clothlab_combination& state, std::size_t i, std::size_t k) const;
  clothlab_status evaluate(const clothlab_combination& x, const clothlab_combination* v, Real* a);

  static clothlab_status eval_callback(void* context, double t, const void* x, const void* v,
                                       void* a);
  static clothlab_status eval_at_callback(void* context, double t, const clothlab_combination* x,
                                          const clothlab_combination* v, void* a);
  static clothlab_status reserve_rkn_callback(void* context, uint32_t stages);
  static clothlab_status step_rkn_callback(void* context, double t, double h,
                                           const clothlab_rkn_scheme* scheme);
  static void axpy_callback(void* context, void* y, double alpha, const void* x);
  static void lincomb_callback(void* context, void* out, const void* base, uint32_t count,
                               const double* coefficients, const void* const* vectors);
  static void copy_callback(void* context, void* dst, const void* src);
  static void* alloc_callback(void* context);

  // Host extensions (reference_extensions.cpp): reductions, external forces and the spring
  // Jacobian as plain serial loops over the spring list (scatter), the topology with
  // first-fit colourings: the oracle for the engine's, and the grid it lies on (its colours
  // are no stencils).
  static const void* get_extension_callback(void* context, const char* id);
  void build_topology(const Scene& scene);
  static clothlab_status topology_get(void* context, clothlab_topology* out);
  static clothlab_status grid_get(void* context, clothlab_grid* out);
  void to_aos(const void* soa, std::vector<Real>& aos) const;
  // M = c_x dF_i/dx_j + c_v dF_i/dv_j of spring s at (x, v), row-major; definite: the form
  // of clothlab.definite-jacobian/1 (no compressive transverse stiffness, no damping x-term).
  void spring_block(const Spring<Real>& s, const Real* x, const Real* v, double c_x, double c_v,
                    bool definite, double (&m)[9]) const;
  uint32_t slot(uint32_t row, uint32_t column) const;
  static clothlab_status jacobian_reserve(void* context);
  template <bool Definite>
  static clothlab_status jacobian_apply(void* context, double t, const void* x, const void* v,
                                        double c_x, double c_v, const void* u, void* out);
  template <bool Definite>
  static clothlab_status jacobian_diagonal(void* context, double t, const void* x, const void* v,
                                           double c_x, double c_v, double* out);
  static clothlab_status jacobian_pattern(void* context, clothlab_block_pattern* out);
  template <bool Definite>
  static clothlab_status jacobian_blocks(void* context, double t, const void* x, const void* v,
                                         double c_x, double c_v, double* values);
  // clothlab.cg-step/1 composed of the calls it fuses: definite apply, the additions and
  // mass_dot; the block product in double.
  static clothlab_status cg_linearise(void* context, double t, const void* x, const void* v,
                                      double c_x, double c_v);
  static clothlab_status cg_product(void* context, double alpha, double beta, const void* z,
                                    void* p, void* solution, void* q, double* p_dot_q);
  static clothlab_status cg_update(void* context, double alpha, const void* q, const void* diagonal,
                                   const void* off_diagonal, void* r, void* z, double* r_dot_r,
                                   double* r_dot_z);
  static double dot(void* context, const void* a, const void* b);
  static double mass_dot(void* context, const void* a, const void* b);
  static double max_abs(void* context, const void* a);
  static clothlab_status external(void* context, double t, const void* x, void* a);
  static int32_t depends_on_position(void* context);

  ReferenceCloth<Real> cloth_;
  bool velocity_forces_;
  std::size_t n_, stride_;
  Vector x_, v_, inverse_mass_;
  std::vector<clothlab_range> active_;
  std::vector<Real> x_aos_, v_aos_, a_aos_;
  std::vector<Vector> vectors_;
  Vector stage_x_, stage_v_;                     // step_rkn: one stage state at a time
  std::vector<Vector> accelerations_;            // step_rkn: one per stage
  std::vector<double> product_;                  // jacobian: 3 n accumulators
  std::vector<uint32_t> row_offsets_, columns_;  // jacobian: block pattern
  std::vector<double> blocks_;                   // jacobian: all blocks, for the diagonal
  struct Linearisation {
    double t = 0.0;
    const void *x = nullptr, *v = nullptr;
    double c_x = 0.0, c_v = 0.0;
  } linearised_;       // cg-step's; x == nullptr: none yet
  bool wind_ = false;  // external forces depend on the state (wind or air)
  struct Topology {
    std::vector<uint32_t> first, second, triangles, adjacency_offsets, adjacent_springs;
    std::vector<uint32_t> spring_color_offsets, spring_color_members;
    std::vector<uint32_t> particle_color_offsets, particle_color_members;
    std::vector<double> rest_length, ks, kd;
    std::vector<uint8_t> family;
  } topology_;
  clothlab_grid grid_{};
  clothlab_system system_{};
  uint64_t force_evals_ = 0;
  double force_seconds_ = 0.0;
};

extern template class ReferenceSystem<float>;
extern template class ReferenceSystem<double>;

}  // namespace clothlab::reference
