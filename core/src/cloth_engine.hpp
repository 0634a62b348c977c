// The cloth's force pipeline and the system callbacks integrators drive it through, on the
// state of EngineState (compiled once; this is compiled per SIMD target).
#pragma once

#include <clothlab/ext/grid.h>

#include <chrono>
#include <clothlab/core/team_governor.hpp>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "aligned_buffer.hpp"
#include "engine_state.hpp"
#include "force_pipeline.hpp"
#include "grid.hpp"
#include "simd_namespace.hpp"
#include "spring_jacobian.hpp"
#include "spring_list_forces.hpp"

namespace clothlab::detail::inline CLOTHLAB_SIMD_NAMESPACE {

template <class Real>
class ClothEngine final : public EngineState<Real> {
  using Base = EngineState<Real>;
  using Base::active_, Base::active_chunks_, Base::active_particles_, Base::inverse_mass_,
      Base::model_, Base::n_, Base::on_grid_path, Base::parallel_, Base::parallel_capable_,
      Base::scene_, Base::stride_, Base::threads_, Base::topology, Base::v_, Base::velocity_forces_,
      Base::x_;
  using typename Base::Span;

 public:
  // `model` is the scene's cloth (build_grid_model or build_mesh_model); the grid's row pipeline
  // runs when it is a grid and options.force_general_path is off, the spring-list path else.
  ClothEngine(const Scene& scene, std::shared_ptr<const ClothModel> model, PipelineOptions options);

  const clothlab_system& system() const override { return system_; }
  // Threads the force and vector passes actually use: small clothes run on one.
  int threads() const override { return parallel_capable_ ? threads_ : 1; }
  void begin_step() override;
  void end_step() override;
  StageCounters& counters() override { return counters_; }

 private:
  clothlab_status evaluate(const StateCombination<Real>& x, const StateCombination<Real>* v,
                           Real* a);
  void axpy(Real* y, Real alpha, const Real* x);
  void lincomb(Real* out, const Real* base, uint32_t count, const double* coefficients,
               const void* const* vectors);
  void* alloc_vector() noexcept;

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

  // Host extensions (cloth_engine_extensions.cpp): topology, jacobian, definite jacobian,
  // cg-step, reductions and external forces. The Jacobian's pattern is built on first use. The
  // grid is offered only on the grid path.
  static const void* get_extension_callback(void* context, const char* id);
  const SpringJacobian<Real>& jacobian();
  // Sum over the active chunks of term(k * stride + i), each chunk summed on its own and
  // the chunks' sums added in chunk order: the same bits for any thread count.
  template <class Term>
  double chunked_sum(Term&& term);
  static clothlab_status topology_callback(void* context, clothlab_topology* out);
  static clothlab_status grid_callback(void* context, clothlab_grid* out);
  static clothlab_status jacobian_reserve_callback(void* context);
  // Definite: the form of clothlab.definite-jacobian/1.
  template <bool Definite>
  static clothlab_status jacobian_apply_callback(void* context, double t, const void* x,
                                                 const void* v, double c_x, double c_v,
                                                 const void* u, void* out);
  static clothlab_status jacobian_pattern_callback(void* context, clothlab_block_pattern* out);
  // The block calls (diagonal blocks, the table) of either form: Method fills `out`.
  using BlockMethod = void (SpringJacobian<Real>::*)(const Real*, const Real*, double, double,
                                                     double*) const;
  template <BlockMethod Method>
  static clothlab_status jacobian_blocks_callback(void* context, double t, const void* x,
                                                  const void* v, double c_x, double c_v,
                                                  double* out);
  static clothlab_status cg_linearise_callback(void* context, double t, const void* x,
                                               const void* v, double c_x, double c_v);
  static clothlab_status cg_product_callback(void* context, double alpha, double beta,
                                             const void* z, void* p, void* solution, void* q,
                                             double* p_dot_q);
  static clothlab_status cg_update_callback(void* context, double alpha, const void* q,
                                            const void* diagonal, const void* off_diagonal, void* r,
                                            void* z, double* r_dot_r, double* r_dot_z);
  // solution += alpha p, p = z + beta p on the active particles: cg-step's direction where the
  // product's sweep does not take it.
  void cg_direction(Real alpha, Real beta, const Real* z, Real* p, Real* solution);
  static double dot_callback(void* context, const void* a, const void* b);
  static double mass_dot_callback(void* context, const void* a, const void* b);
  static double max_abs_callback(void* context, const void* a);
  static clothlab_status external_callback(void* context, double t, const void* x, void* a);
  static int32_t depends_on_position_callback(void* context);
  // clothlab.external-forces/2: offered on the grid path where the pipeline's rows are the
  // grid's (not turned), so that a range of rows costs its rows alone.
  bool offers_external_rows() const { return forces_ && forces_->rows_are_grid_rows(); }
  static clothlab_status external_rows_callback(void* context, double t, const void* x, void* a,
                                                uint32_t row_begin, uint32_t row_end,
                                                uint32_t slot);
  static int32_t depends_on_velocity_callback(void* context);
  static uint32_t threads_callback(void* context);
  // clothlab.contacts/1 and clothlab.attachment-targets/1 (EngineState's).
  static clothlab_status contacts_resolve_callback(void* context, double t, void* x, void* v);
  static uint32_t attachments_count_callback(void* context);
  static clothlab_status attachments_move_callback(void* context, double t, void* x, void* v);

  std::vector<clothlab_grid_color> grid_colors_;  // the grid path's spring colours as stencils
  TeamGovernor governor_{1, false};
  std::chrono::steady_clock::time_point step_start_{};

  std::unique_ptr<ForcePipeline<Real>> forces_;      // the grid path, or
  std::unique_ptr<SpringListForces<Real>> general_;  // the spring-list path
  std::unique_ptr<SpringJacobian<Real>> jacobian_;
  std::vector<double> chunk_sums_;    // one per active chunk: the reductions' partial results
  std::vector<double> chunk_sums_z_;  // cg-step's update: the chunks' shares of <r, z>
  std::vector<double> mass_;          // 1 / inverse mass (0 where pinned), for mass_dot
  AlignedBuffer<Real> real_mass_;     // the same in the system's precision, for cg-step's update

  std::vector<AlignedBuffer<Real>> vectors_;  // handed out by alloc_vector
  clothlab_system system_{};
  StageCounters counters_;
};

}  // namespace clothlab::detail::inline CLOTHLAB_SIMD_NAMESPACE
