// XPBD: the springs as compliant distance constraints (Macklin, Mueller, Chentanez 2016,
// "XPBD: position-based simulation of compliant constrained dynamics"), stepped with
// substeps of one iteration each by default (Macklin et al. 2019, "Small steps in physics
// simulation").
//
// Per substep of length h = dt / substeps:
//   predict    v += h a_ext(x),  dx = h v,  x += dx            (gravity, wind: the host's
//                                                             external-forces extension)
//   project    lambda = 0, then `iterations` Gauss-Seidel sweeps over the springs, colour
//              by colour (the topology extension's independent sets), each colour's springs
//              in parallel: no two share a particle, so every thread count gives the same bits
//   velocity   v = dx / h
// The substep's displacement dx is kept beside x and moved with every correction, so v never
// comes from x - x_prev: in float32 a substep's motion (g h^2 is ~1e-8 m at h = 25 us) is
// below the rounding of x itself and would be lost, and the cloth would not start to fall.
//
// One spring k joining i and j, C = |x_i - x_j| - rest, n = (x_i - x_j) / |x_i - x_j|:
// compliance alpha = 1 / ks and Rayleigh damping beta = kd (the spring's damping force
// -kd (n . (v_i - v_j)) n is -beta grad C dC/dt), so with alpha~ = alpha / h^2,
// beta~ = h^2 beta and gamma = alpha~ beta~ / h = alpha beta / h the paper's eq. 26 reads
//   dlambda = (-C - alpha~ lambda - gamma n.(dx_i - dx_j)) / ((1 + gamma)(w_i + w_j) + alpha~)
// with dx the substep's displacement. Multiplied through by ks h^2 it needs no division by ks (a
// spring with ks = 0 is a pure damper) and its denominator is >= 1:
//   dlambda = (-ks h^2 C - lambda - kd h n.(dx_i - dx_j)) / ((ks h^2 + kd h)(w_i + w_j) + 1)
//   x_i += w_i dlambda n,  x_j -= w_j dlambda n.
// lambda accumulates over the iterations of a substep and is reset once per substep, never
// per iteration: resetting it per iteration would make the stiffness grow with the iteration
// count (the peer bug newton#2933).
//
// Accuracy: one converged projection per substep is backward Euler on the elastic dynamics
// (same equation as its Newton step for a single spring), so XPBD converges at first order
// in h to the spring dynamics with the scene's ks and kd; one iteration per substep adds an
// O(h^2) per-step Gauss-Seidel error, which keeps the method first order.
#include <omp.h>

#include <algorithm>
#include <array>
#include <clothlab/sdk.hpp>
#include <cmath>
#include <cstdint>
#include <vector>

#include "scratch_vectors.hpp"

namespace clothlab::builtin {
namespace {

// Smaller clothes run on the calling thread: a colour of fewer than ~5000 springs is not
// worth the barrier that ends it (12 barriers per sweep).
constexpr uint32_t parallel_from_springs = 65536;

// One spring as the projection reads it, stored colour by colour.
template <class Real>
struct Constraint {
  uint32_t first, second;
  Real rest, ks, kd;
  Real first_weight, second_weight;  // inverse masses; 0 for a pinned end
};

// The constraints of one precision and their multipliers (lambda, one per constraint).
template <class Real>
struct Constraints {
  std::vector<Constraint<Real>> springs;
  std::vector<Real> lambda;
};

}  // namespace

struct Xpbd {
  static constexpr const char* id = "xpbd";
  static constexpr const char* name = "XPBD distance constraints with substeps";
  static constexpr const char* version = "1.0.0";
  static constexpr const char* description =
      "Macklin et al. 2016/2019: springs as compliant constraints (alpha = 1/ks, damping "
      "eq. 26), Gauss-Seidel by spring colour, substeps; first order, unconditionally stable";
  static constexpr uint32_t order = 1;
  // No eval_acceleration calls: its cost is substeps x iterations passes over the springs.
  static constexpr uint32_t evals_per_step = 0;
  // The damping (kd) is part of the constraint projection; the flag makes the host and the
  // conformance runner treat the scene's damping as present.
  static constexpr uint32_t flags = CLOTHLAB_INTEGRATOR_USES_VELOCITY_FORCES;
  static constexpr std::array<clothlab_param_spec, 3> params{
      sdk::int_param("substeps", 40, 1, 1000, "substeps per step (h = dt / substeps)"),
      sdk::int_param("iterations", 1, 1, 100, "Gauss-Seidel sweeps over the springs per substep"),
      sdk::int_param("threads", 0, 0, 256,
                     "threads for the colour sweeps; 0 = all (omp_get_max_threads)"),
  };
  static constexpr clothlab_integrator_traits traits{
      sizeof(clothlab_integrator_traits),
      CLOTHLAB_TRAIT_UNCONDITIONALLY_STABLE | CLOTHLAB_TRAIT_ITERATIVE, "substeps", "iterations"};

  explicit Xpbd(const sdk::Params& values)
      : substeps_(static_cast<int>(values.integer("substeps"))),
        iterations_(static_cast<int>(values.integer("iterations"))),
        requested_threads_(static_cast<int>(values.integer("threads"))) {}

  template <class Real>
  void prepare(sdk::System<Real>& system) {
    const sdk::Topology topology = system.topology();
    (void)system.external_forces();  // fails here, not in step, when the host lacks it
    scratch_.allocate(system);
    Constraints<Real>& constraints = constraints_for<Real>();
    build_constraints(system, topology, constraints.springs);
    constraints.lambda.assign(constraints.springs.size(), 0);
    const int threads = requested_threads_ == 0 ? omp_get_max_threads() : requested_threads_;
    threads_ = topology.spring_count() >= parallel_from_springs ? std::max(threads, 1) : 1;
    // The first parallel region builds the thread team (allocates): here, not in step.
    if (threads_ > 1) {
#pragma omp parallel num_threads(threads_)
      { (void)omp_get_thread_num(); }
    }
  }

  template <class Real>
  void step(sdk::System<Real>& system, double t, double dt) {
    const auto [external_acceleration, displacement] = scratch_.bind(system);
    if (dt == 0.0) return;
    const sdk::ExternalForces<Real> external = system.external_forces();
    const bool wind = external.depends_on_position();
    const double h = dt / substeps_;
    if (!wind) external.acceleration(t, system.x(), external_acceleration);
    for (int substep = 0; substep < substeps_; ++substep) {
      if (wind) external.acceleration(t + substep * h, system.x(), external_acceleration);
      if (!advance_substep(system, h, external_acceleration, displacement))
        throw sdk::Error(CLOTHLAB_ERROR_NUMERICAL, "non-finite velocity in the substep at t = " +
                                                       std::to_string(t + substep * h));
    }
  }

 private:
  template <class Real>
  Constraints<Real>& constraints_for() {
    if constexpr (sizeof(Real) == 4)
      return constraints_f32_;
    else
      return constraints_f64_;
  }

  // Copies the springs colour by colour; springs with both ends pinned never move and are
  // left out (their colour ranges shrink accordingly).
  template <class Real>
  void build_constraints(const sdk::System<Real>& system, const sdk::Topology& topology,
                         std::vector<Constraint<Real>>& out) {
    const Real* inverse_mass = system.inverse_mass();
    out.clear();
    out.reserve(topology.spring_count());
    color_offsets_.assign(1, 0);
    for (uint32_t color = 0; color < topology.spring_color_count(); ++color) {
      for (uint32_t k : topology.spring_color(color)) {
        const uint32_t i = topology.first()[k], j = topology.second()[k];
        if (inverse_mass[i] == 0 && inverse_mass[j] == 0) continue;
        out.push_back({i, j, static_cast<Real>(topology.rest_length()[k]),
                       static_cast<Real>(topology.ks()[k]), static_cast<Real>(topology.kd()[k]),
                       inverse_mass[i], inverse_mass[j]});
      }
      color_offsets_.push_back(static_cast<uint32_t>(out.size()));
    }
  }

  // One substep; false when a velocity came out non-finite. The sweeps' worksharing loops
  // run on the team of a parallel region, or, on one thread, orphaned (no team, no barrier
  // cost, no allocation).
  template <class Real>
  bool advance_substep(sdk::System<Real>& system, double h, const Real* external_acceleration,
                       Real* displacement) {
    const Substep<Real> substep{constraints_for<Real>().springs.data(),
                                constraints_for<Real>().lambda.data(),
                                system.inverse_mass(),
                                external_acceleration,
                                displacement,
                                system.x(),
                                system.v(),
                                system.particle_count(),
                                system.stride(),
                                static_cast<Real>(h),
                                static_cast<Real>(h * h),
                                static_cast<Real>(1.0 / h)};
    if (threads_ == 1) return sweep(substep);
    bool finite = true;
#pragma omp parallel num_threads(threads_) reduction(&& : finite)
    finite = sweep(substep);
    return finite;
  }

  template <class Real>
  struct Substep {
    const Constraint<Real>* constraints;
    Real* lambda;
    const Real* inverse_mass;
    const Real* external_acceleration;
    Real* displacement;  // x's change in this substep, exact where x's rounding is not
    Real* x;
    Real* v;
    uint32_t particle_count;
    std::size_t stride;
    Real h, h_squared, inverse_h;
  };

  // Predict, project colour by colour, update velocities. Returns this thread's share of
  // "every velocity is finite".
  template <class Real>
  bool sweep(const Substep<Real>& s) const {
    const auto n = static_cast<long>(s.particle_count);
#pragma omp for schedule(static)
    for (long i = 0; i < n; ++i)
      for (std::size_t c = 0; c < 3; ++c) {
        const std::size_t e = c * s.stride + static_cast<std::size_t>(i);
        s.displacement[e] = 0;  // pinned too: their dx must be 0
        if (s.inverse_mass[i] == 0) continue;
        s.v[e] += s.h * s.external_acceleration[e];
        s.displacement[e] = s.h * s.v[e];
        s.x[e] += s.displacement[e];
      }
    for (int iteration = 0; iteration < iterations_; ++iteration)
      for (std::size_t color = 0; color + 1 < color_offsets_.size(); ++color) {
        const long begin = color_offsets_[color], end = color_offsets_[color + 1];
#pragma omp for schedule(static)
        for (long k = begin; k < end; ++k)
          project(s.constraints[k], s.lambda[k], iteration == 0, s.x, s.displacement, s.stride, s.h,
                  s.h_squared);
      }
    bool finite = true;
#pragma omp for schedule(static)
    for (long i = 0; i < n; ++i) {
      if (s.inverse_mass[i] == 0) continue;
      for (std::size_t c = 0; c < 3; ++c) {
        const std::size_t e = c * s.stride + static_cast<std::size_t>(i);
        s.v[e] = s.displacement[e] * s.inverse_h;
        finite = finite && std::isfinite(s.v[e]);
      }
    }
    return finite;
  }

  template <class Real>
  // lambda is reset at the substep's first iteration (`fresh`), then accumulates.
  static void project(const Constraint<Real>& spring, Real& lambda, bool fresh, Real* x,
                      Real* displacement, std::size_t stride, Real h, Real h_squared) {
    std::array<Real, 3> d, moved;
    for (std::size_t c = 0; c < 3; ++c) {
      const std::size_t i = c * stride + spring.first, j = c * stride + spring.second;
      d[c] = x[i] - x[j];
      moved[c] = displacement[i] - displacement[j];
    }
    const Real accumulated = fresh ? Real(0) : lambda;
    lambda = accumulated;
    const Real length = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    if (!(length > 0)) return;  // coincident ends: no direction to push along
    const Real inverse_length = 1 / length;
    const Real stiffness = spring.ks * h_squared, damping = spring.kd * h;
    const Real closing = (d[0] * moved[0] + d[1] * moved[1] + d[2] * moved[2]) * inverse_length;
    const Real delta = (-stiffness * (length - spring.rest) - lambda - damping * closing) /
                       ((stiffness + damping) * (spring.first_weight + spring.second_weight) + 1);
    lambda += delta;
    const Real push_first = spring.first_weight * delta * inverse_length;
    const Real push_second = spring.second_weight * delta * inverse_length;
    for (std::size_t c = 0; c < 3; ++c) {
      const std::size_t i = c * stride + spring.first, j = c * stride + spring.second;
      if (spring.first_weight != 0) {
        x[i] += push_first * d[c];
        displacement[i] += push_first * d[c];
      }
      if (spring.second_weight != 0) {
        x[j] -= push_second * d[c];
        displacement[j] -= push_second * d[c];
      }
    }
  }

  int substeps_;
  int iterations_;
  int requested_threads_;
  int threads_ = 1;
  Constraints<float> constraints_f32_;
  Constraints<double> constraints_f64_;
  std::vector<uint32_t> color_offsets_;  // constraints of colour c: [offsets[c], offsets[c + 1])
  ScratchVectors<2> scratch_;            // external acceleration, the substep's displacement
};

}  // namespace clothlab::builtin

CLOTHLAB_PLUGIN_ENTRY("clothlab-builtin-xpbd", "1.0.0",
                      clothlab::sdk::integrators<clothlab::builtin::Xpbd>,
                      clothlab::sdk::scenarios<>)
