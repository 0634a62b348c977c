// The cloth state in one precision (SoA, 64-byte aligned, stride a multiple of 16), its
// force pipeline and the system callbacks integrators drive it through.
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
#include "engine.hpp"
#include "force_pipeline.hpp"
#include "grid.hpp"
#include "simd_namespace.hpp"
#include "spring_jacobian.hpp"
#include "spring_list_forces.hpp"

namespace clothlab::detail::inline CLOTHLAB_SIMD_NAMESPACE {

template <class Real>
class ClothEngine final : public Engine {
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

  void positions(std::vector<double>& out) const override;
  void velocities(std::vector<double>& out) const override;
  void positions(std::vector<float>& out) const override;
  void velocities(std::vector<float>& out) const override;
  void set_state(const std::vector<double>& x, const std::vector<double>& v) override;
  void copy_raw_state(Cloth::RawState& out) const override;
  void set_raw_state(const Cloth::RawState& state) override;
  bool state_is_finite() const override;
  Cloth::Energy energy() const override;
  Cloth::Stretch stretch(Cloth::Springs springs) const override;
  double stretch_percentile(Cloth::Springs springs, double fraction) const override;
  Cloth::LongestSpring longest_spring(Cloth::Springs springs) const override;
  void set_colliders(std::span<const Collider> colliders, double t) override;
  Cloth::Contacts contacts() const override;
  std::span<const Collider> colliders() const override { return colliders_; }
  void set_attachments(std::span<const uint32_t> particles, AttachmentSource& source) override;
  bool move_attachments(double t) override;
  void pin_loads(Cloth::PinLoads& out) const override;
  Cloth::Momentum free_momentum() const override;
  double contact_work() const override { return contact_work_; }

 private:
  struct Span {
    std::size_t begin, end;
  };

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
  const ClothModel& topology() const { return *model_; }
  bool on_grid_path() const { return forces_ != nullptr; }
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
  template <bool Definite>
  static clothlab_status jacobian_diagonal_callback(void* context, double t, const void* x,
                                                    const void* v, double c_x, double c_v,
                                                    double* out);
  static clothlab_status jacobian_pattern_callback(void* context, clothlab_block_pattern* out);
  static clothlab_status jacobian_blocks_callback(void* context, double t, const void* x,
                                                  const void* v, double c_x, double c_v,
                                                  double* values);
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
  static uint32_t threads_callback(void* context);
  // clothlab.contacts/1 (cloth_engine_contacts.cpp).
  static clothlab_status contacts_resolve_callback(void* context, double t, void* x, void* v);
  // clothlab.attachment-targets/1 (cloth_engine_attachments.cpp).
  static uint32_t attachments_count_callback(void* context);
  static clothlab_status attachments_move_callback(void* context, double t, void* x, void* v);

  Scene scene_;
  std::shared_ptr<const ClothModel> model_;
  std::vector<clothlab_grid_color> grid_colors_;  // the grid path's spring colours as stencils
  std::size_t n_ = 0;
  std::size_t stride_ = 0;
  int threads_ = 1;
  bool parallel_capable_ = false;  // the cloth is large enough for the team
  bool parallel_ = false;          // this step runs on the team
  TeamGovernor governor_{1, false};
  std::chrono::steady_clock::time_point step_start_{};

  AlignedBuffer<Real> x_, v_, inverse_mass_;
  // 1 where a pinned particle lies within two rows and two columns (on a mesh: two springs):
  // the springs that Stretch::max_away_from_pins leaves out.
  std::vector<uint8_t> near_pin_;
  mutable std::vector<double> stretch_ratios_;  // stretch_percentile's selection
  std::vector<clothlab_range> active_;
  std::vector<Span> active_chunks_;  // active ranges cut into pieces for threads
  uint64_t active_particles_ = 0;

  std::unique_ptr<ForcePipeline<Real>> forces_;      // the grid path, or
  std::unique_ptr<SpringListForces<Real>> general_;  // the spring-list path
  bool velocity_forces_ = true;
  std::unique_ptr<SpringJacobian<Real>> jacobian_;
  std::vector<double> chunk_sums_;    // one per active chunk: the reductions' partial results
  std::vector<double> chunk_sums_z_;  // cg-step's update: the chunks' shares of <r, z>
  std::vector<double> mass_;          // 1 / inverse mass (0 where pinned), for mass_dot
  AlignedBuffer<Real> real_mass_;     // the same in the system's precision, for cg-step's update

  std::vector<Collider> step_colliders_;   // as the host set them at the step's start
  double step_start_time_ = 0;             // when
  std::vector<Collider> colliders_;        // at the last resolution (or the step's start)
  std::vector<Collider> moved_colliders_;  // the resolution's scratch: at its time
  AlignedBuffer<Real> path_start_;  // where each particle was at the last resolution or step start
  AlignedBuffer<Real> step_start_x_;         // where each particle was at the step's start
  uint32_t particles_crossed_ = 0;           // in the step before the last set_colliders
  std::vector<uint32_t> attached_;           // particles moved to the source's targets
  std::vector<double> target_x_, target_v_;  // their targets, 3 per particle
  AttachmentSource* attachment_source_ = nullptr;
  double contact_work_ = 0;  // energy the contact resolution has added (J)
  // Diagnostics over the spring list (the general path; cloth_engine_state.cpp).
  double list_spring_energy() const;
  // visit(length / rest length, first, second) for each spring (structural ones alone).
  template <class Visit>
  void for_each_ratio(Cloth::Springs which, Visit&& visit) const;
  // The energy of particle i's springs with x_i at `position` and its partners in px.
  double spring_energy_at(const Real* px, std::size_t i, const Vec3& position) const;
  std::vector<AlignedBuffer<Real>> vectors_;  // handed out by alloc_vector
  clothlab_system system_{};
  StageCounters counters_;
};

}  // namespace clothlab::detail::inline CLOTHLAB_SIMD_NAMESPACE
