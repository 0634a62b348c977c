// Preconditioned conjugate gradients on A = I + c_x J_x + c_v J_v (J the spring Jacobian
// clothlab.jacobian/1, or its definite form clothlab.definite-jacobian/1) at a state (x, v), in
// the mass inner product: M A is symmetric, so CG runs in <a, b> = a^T M b and the tolerance is
// on |r|_M / |b|_M. The preconditioner is the inverted 3x3 diagonal blocks of A (block-Jacobi),
// or, where a MultigridPreconditioner is given, its V-cycle (the host's update sweep applies
// block-Jacobi only: with the V-cycle, CG and the V-cycle's fine smoother take the host's
// linearised product, and the rest runs in separate calls).
// Pinned particles drop out: every host vector operation and product acts on the active
// particles only, so the solution's pinned entries stay as they were.
//
// With the definite matrix on a host that offers clothlab.cg-step/1, the solve linearises A once
// and an iteration is two host sweeps: the product with <p, Ap>, carrying the last iteration's
// solution and direction updates, and the residual and preconditioner updates with <r, r> and
// <r, z> (with the V-cycle: the product's sweep, then the residual's axpy, the V-cycle and the
// dot products); otherwise the same iteration in separate host calls. implicit_euler solves with
// it, and bench/microbench.cpp's cg_iteration times `iterate` itself.
#pragma once

#include <algorithm>
#include <array>
#include <clothlab/sdk.hpp>
#include <cmath>
#include <cstddef>
#include <optional>
#include <vector>

#include "multigrid_preconditioner.hpp"

namespace clothlab::builtin {

template <class Real>
class PreconditionedCg {
 public:
  // CG's vectors of the system: r, z, p, q, then the fused path's preconditioner blocks.
  static constexpr std::size_t vector_count = 6;
  enum class Outcome { kRunning, kConverged, kBreakdown };

  // inverse_blocks: 9 n doubles of scratch. use_cg_step = false keeps the separate calls even
  // where the host offers clothlab.cg-step/1 (to compare both). multigrid: the preconditioner
  // instead of block-Jacobi, prepared for this system; nullptr for block-Jacobi.
  PreconditionedCg(const sdk::System<Real>& system, const std::array<Real*, vector_count>& vectors,
                   std::vector<double>& inverse_blocks, bool definite, bool use_cg_step = true,
                   MultigridPreconditioner* multigrid = nullptr)
      : system_(system),
        jacobian_(system.jacobian()),
        definite_(definite ? std::optional{system.definite_jacobian()} : std::nullopt),
        cg_step_(definite && use_cg_step &&
                         system.template extension<clothlab_cg_step_extension>(
                             CLOTHLAB_EXT_CG_STEP) != nullptr
                     ? std::optional{system.cg_step()}
                     : std::nullopt),
        reductions_(system.reductions()),
        r_(vectors[0]),
        z_(vectors[1]),
        p_(vectors[2]),
        q_(vectors[3]),
        block_diagonal_(vectors[4]),
        block_off_diagonal_(vectors[5]),
        inverse_blocks_(inverse_blocks),
        multigrid_(multigrid) {}

  // Whether an iteration is the host's two sweeps (block-Jacobi only).
  bool fused() const { return cg_step_.has_value() && multigrid_ == nullptr; }

  // Readies a solve of A solution = rhs at (x, v), with A = I + J for J's weights c_x = -h^2,
  // c_v = -h: the preconditioner and the residual of `solution` (guess) or of 0 (solution
  // zeroed by the caller). x, v, rhs and solution must outlive the solve.
  void start(double t, double h, const Real* x, const Real* v, const Real* rhs, Real* solution,
             bool guess, double tolerance) {
    t_ = t, x_ = x, v_ = v, solution_ = solution, pending_ = false;
    c_x_ = -h * h, c_v_ = -h;
    if (cg_step_) cg_step_->linearise(t, x, v, c_x_, c_v_);
    if (multigrid_ != nullptr) {
      multigrid_->prepare_solve(
          system_, c_x_, [this](const Real* u, Real* out) { apply_shifted(u, out); },
          [this](double* values) { definite_->blocks(t_, x_, v_, c_x_, c_v_, values); });
    } else {
      invert_diagonal_blocks();
    }
    if (guess) {  // r = rhs - A solution
      apply(solution, q_);
      system_.template lincomb<2>(r_, rhs, {-1.0, -1.0}, {solution, q_});
    } else {
      system_.copy(r_, rhs);
    }
    rhs_norm_ = std::sqrt(reductions_.mass_dot(rhs, rhs));
    residual_norm_ = guess ? std::sqrt(reductions_.mass_dot(r_, r_)) : rhs_norm_;
    goal_ = tolerance * rhs_norm_;
    if (residual_norm_ <= goal_) return;
    precondition(r_, z_);
    system_.copy(p_, z_);
    rz_ = reductions_.mass_dot(r_, z_);
  }

  bool converged() const { return residual_norm_ <= goal_; }

  // One CG iteration; kBreakdown where A is not positive along p (p.Ap <= 0), which leaves the
  // solution as it was.
  Outcome iterate() {
    double pq = 0.0;
    if (cg_step_) {  // with the last iteration's solution and direction updates, if pending
      pq = pending_ ? cg_step_->product(alpha_, beta_, z_, p_, solution_, q_)
                    : cg_step_->product(p_, q_);
      pending_ = false;
    } else {
      apply(p_, q_);
      system_.axpy(q_, 1.0, p_);
      pq = reductions_.mass_dot(p_, q_);
    }
    if (!std::isfinite(pq)) throw sdk::Error(CLOTHLAB_ERROR_NUMERICAL, "CG met a non-finite p.Ap");
    if (pq <= 0.0) return Outcome::kBreakdown;
    const double alpha = rz_ / pq;
    double rz_next = 0.0;
    if (cg_step_) {
      if (fused()) {
        const auto residual =
            cg_step_->update(alpha, q_, block_diagonal_, block_off_diagonal_, r_, z_);
        residual_norm_ = std::sqrt(residual.r_dot_r);
        rz_next = residual.r_dot_z;
      } else {
        system_.axpy(r_, -alpha, q_);
        residual_norm_ = std::sqrt(reductions_.mass_dot(r_, r_));
      }
      if (converged()) {
        system_.axpy(solution_, alpha, p_);
        return Outcome::kConverged;
      }
      if (!fused()) {
        precondition(r_, z_);
        rz_next = reductions_.mass_dot(r_, z_);
      }
      alpha_ = alpha, beta_ = rz_next / rz_, pending_ = true;
    } else {
      system_.axpy(solution_, alpha, p_);
      system_.axpy(r_, -alpha, q_);
      residual_norm_ = std::sqrt(reductions_.mass_dot(r_, r_));
      if (converged()) return Outcome::kConverged;
      precondition(r_, z_);
      rz_next = reductions_.mass_dot(r_, z_);
      system_.template lincomb<1>(p_, z_, {rz_next / rz_}, {p_});
    }
    rz_ = rz_next;
    return Outcome::kRunning;
  }

  // Completes the solution after the last iterate (the fused path defers alpha p to the next
  // product's sweep).
  void finish() {
    if (pending_) system_.axpy(solution_, alpha_, p_);
    pending_ = false;
  }

  double rhs_norm() const { return rhs_norm_; }
  double residual_norm() const { return residual_norm_; }

 private:
  // q = J u with the solve's weights.
  void apply(const Real* u, Real* q) const {
    if (definite_) return definite_->apply(t_, x_, v_, c_x_, c_v_, u, q);
    jacobian_.apply(t_, x_, v_, c_x_, c_v_, u, q);
  }

  // q = A u = u + J u on the active particles: the host's linearised product where it offers
  // one (linearised in `start`), else J's product and an axpy.
  void apply_shifted(const Real* u, Real* q) const {
    if (cg_step_) return void(cg_step_->product(u, q));
    apply(u, q);
    system_.axpy(q, 1.0, u);
  }

  // inverse_blocks_ = inverses of the 3x3 diagonal blocks of A; a block too close to singular
  // (indefinite A) falls back to the identity. The fused path takes them as symmetric blocks
  // in the system's precision (the definite A's blocks are symmetric).
  void invert_diagonal_blocks() {
    if (definite_) {
      definite_->diagonal_blocks(t_, x_, v_, c_x_, c_v_, inverse_blocks_.data());
    } else {
      jacobian_.diagonal_blocks(t_, x_, v_, c_x_, c_v_, inverse_blocks_.data());
    }
    const std::size_t stride = system_.stride();
    for (const clothlab_range& range : system_.active())
      for (uint32_t i = range.begin; i < range.end; ++i) {
        double* b = &inverse_blocks_[9 * std::size_t{i}];
        invert_block(b);
        if (!cg_step_) continue;
        block_diagonal_[i] = static_cast<Real>(b[0]);
        block_diagonal_[stride + i] = static_cast<Real>(b[4]);
        block_diagonal_[2 * stride + i] = static_cast<Real>(b[8]);
        block_off_diagonal_[i] = static_cast<Real>(b[1]);
        block_off_diagonal_[stride + i] = static_cast<Real>(b[2]);
        block_off_diagonal_[2 * stride + i] = static_cast<Real>(b[5]);
      }
  }

  // b = (I + b)^-1, row-major, or I where I + b is close to singular.
  static void invert_block(double* b) {
    b[0] += 1.0, b[4] += 1.0, b[8] += 1.0;
    const std::array<double, 9> cofactor{
        b[4] * b[8] - b[5] * b[7], b[2] * b[7] - b[1] * b[8], b[1] * b[5] - b[2] * b[4],
        b[5] * b[6] - b[3] * b[8], b[0] * b[8] - b[2] * b[6], b[2] * b[3] - b[0] * b[5],
        b[3] * b[7] - b[4] * b[6], b[1] * b[6] - b[0] * b[7], b[0] * b[4] - b[1] * b[3]};
    const double determinant = b[0] * cofactor[0] + b[1] * cofactor[3] + b[2] * cofactor[6];
    const double scale = std::max({std::abs(b[0]), std::abs(b[4]), std::abs(b[8])});
    if (!(std::abs(determinant) > 1e-12 * scale * scale * scale)) {
      std::fill(b, b + 9, 0.0);
      b[0] = b[4] = b[8] = 1.0;
      return;
    }
    for (int k = 0; k < 9; ++k) b[k] = cofactor[k] / determinant;
  }

  // z = blockdiag(A)^-1 r, or the multigrid's z, on the active particles.
  void precondition(const Real* r, Real* z) const {
    if (multigrid_ != nullptr)
      return multigrid_->apply(system_, r, z,
                               [this](const Real* u, Real* out) { apply_shifted(u, out); });
    const std::size_t stride = system_.stride();
    for (const clothlab_range& range : system_.active())
      for (uint32_t i = range.begin; i < range.end; ++i) {
        const double* b = &inverse_blocks_[9 * std::size_t{i}];
        const double r0 = r[i], r1 = r[stride + i], r2 = r[2 * stride + i];
        z[i] = static_cast<Real>(b[0] * r0 + b[1] * r1 + b[2] * r2);
        z[stride + i] = static_cast<Real>(b[3] * r0 + b[4] * r1 + b[5] * r2);
        z[2 * stride + i] = static_cast<Real>(b[6] * r0 + b[7] * r1 + b[8] * r2);
      }
  }

  const sdk::System<Real>& system_;
  sdk::Jacobian<Real> jacobian_;
  std::optional<sdk::DefiniteJacobian<Real>> definite_;  // with the definite matrix only
  std::optional<sdk::CgStep<Real>> cg_step_;             // the fused sweeps, where offered
  sdk::Reductions<Real> reductions_;
  Real *r_, *z_, *p_, *q_, *block_diagonal_, *block_off_diagonal_;
  std::vector<double>& inverse_blocks_;
  MultigridPreconditioner* multigrid_;
  double t_ = 0.0, c_x_ = 0.0, c_v_ = 0.0;
  const Real *x_ = nullptr, *v_ = nullptr;
  Real* solution_ = nullptr;
  double rhs_norm_ = 0.0, residual_norm_ = 0.0, goal_ = 0.0, rz_ = 0.0;
  bool pending_ = false;  // fused: solution += alpha_ p, p = z + beta_ p not applied yet
  double alpha_ = 0.0, beta_ = 0.0;
};

}  // namespace clothlab::builtin
