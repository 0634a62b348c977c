#include "clothlab/analysis/spectral_estimate.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>

#include "clothlab/analysis/linearised_system.hpp"

namespace clothlab::analysis {
namespace {

using Vector = std::vector<double>;
using Complex = std::complex<double>;

Vector random_active_vector(LinearisedSystem& lin, std::mt19937_64& random) {
  std::normal_distribution<double> normal;
  Vector u(lin.vector_size());
  for (double& value : u) value = normal(random);
  lin.keep_active(u);
  return u;
}

void scale(Vector& u, double factor) {
  for (double& value : u) value *= factor;
}

struct PowerResult {
  double rayleigh = 0.0;  // u.Ju / u.u at the last iterate
  Vector vector;
  bool converged = false;
};

// Dominant eigenvalue (by modulus) of a symmetric-like operator; its sign is kept.
template <class Apply>
PowerResult power_iteration(LinearisedSystem& lin, Apply apply, Vector start,
                            const SpectralOptions& options) {
  PowerResult result;
  Vector image(start.size());
  scale(start, 1.0 / std::sqrt(lin.dot(start, start)));
  double previous = 0.0;
  for (int iteration = 0; iteration < options.max_iterations; ++iteration) {
    apply(start, image);
    result.rayleigh = lin.dot(start, image);
    const double norm = std::sqrt(lin.dot(image, image));
    if (norm == 0.0) {  // the operator vanishes on the active set
      result.converged = true;
      break;
    }
    std::swap(start, image);
    scale(start, 1.0 / norm);
    if (iteration > 0 &&
        std::abs(result.rayleigh - previous) <= options.tolerance * std::abs(result.rayleigh)) {
      result.converged = true;
      break;
    }
    previous = result.rayleigh;
  }
  result.vector = std::move(start);
  return result;
}

// First-order operator on y = (p, q): A y = (q, J_x p + J_v q).
struct FirstOrderOperator {
  LinearisedSystem& lin;
  Vector stiff, damp;

  explicit FirstOrderOperator(LinearisedSystem& l)
      : lin(l), stiff(l.vector_size()), damp(l.vector_size()) {}

  void apply(const Vector& y, Vector& out) {
    const std::size_t n = lin.vector_size();
    std::span<const double> p(y.data(), n), q(y.data() + n, n);
    lin.position_jacobian(p, stiff);
    lin.velocity_jacobian(q, damp);
    std::copy(q.begin(), q.end(), out.begin());
    for (std::size_t i = 0; i < n; ++i) out[n + i] = stiff[i] + damp[i];
  }
  double dot(const Vector& a, const Vector& b) const {
    const std::size_t n = lin.vector_size();
    return lin.dot(std::span(a.data(), n), std::span(b.data(), n)) +
           lin.dot(std::span(a.data() + n, n), std::span(b.data() + n, n));
  }
};

struct RitzValue {
  Complex value;
  double residual;
  Eigen::VectorXcd coefficients;
};

struct ArnoldiResult {
  std::vector<RitzValue> ritz;  // largest modulus first
  std::vector<Vector> basis;  // of the last restart: Ritz vector i is basis * ritz[i].coefficients
};

// Explicitly restarted Arnoldi, restarting from the real part of the dominant Ritz vector.
ArnoldiResult arnoldi(FirstOrderOperator& op, Vector start, const SpectralOptions& options) {
  const int m = std::max(2, options.krylov_dimension);
  std::vector<RitzValue> ritz;
  std::vector<Vector> basis;
  for (int restart = 0; restart <= options.arnoldi_restarts; ++restart) {
    basis.clear();
    Eigen::MatrixXd hessenberg = Eigen::MatrixXd::Zero(m + 1, m);
    scale(start, 1.0 / std::sqrt(op.dot(start, start)));
    basis.push_back(start);
    int size = m;
    for (int j = 0; j < m; ++j) {
      Vector w(start.size());
      op.apply(basis[j], w);
      for (int pass = 0; pass < 2; ++pass) {  // Gram-Schmidt twice keeps the basis orthogonal
        for (int i = 0; i <= j; ++i) {
          const double h = op.dot(basis[i], w);
          hessenberg(i, j) += h;
          for (std::size_t k = 0; k < w.size(); ++k) w[k] -= h * basis[i][k];
        }
      }
      const double norm = std::sqrt(op.dot(w, w));
      hessenberg(j + 1, j) = norm;
      if (norm <= 1e-300) {  // invariant subspace found: the Ritz values are exact
        size = j + 1;
        break;
      }
      scale(w, 1.0 / norm);
      basis.push_back(std::move(w));
    }
    Eigen::EigenSolver<Eigen::MatrixXd> solver(hessenberg.topLeftCorner(size, size));
    const double beta = hessenberg(size, size - 1);
    ritz.clear();
    for (int i = 0; i < size; ++i) {
      const Eigen::VectorXcd y = solver.eigenvectors().col(i);
      ritz.push_back({solver.eigenvalues()(i), beta * std::abs(y(size - 1)) / y.norm(), y});
    }
    std::sort(ritz.begin(), ritz.end(), [](const RitzValue& a, const RitzValue& b) {
      return std::abs(a.value) > std::abs(b.value);
    });
    const RitzValue& dominant = ritz.front();
    if (dominant.residual <= 1e-6 * std::abs(dominant.value) ||
        restart == options.arnoldi_restarts) {
      break;
    }
    std::fill(start.begin(), start.end(), 0.0);
    for (int i = 0; i < size; ++i) {
      const double weight = dominant.coefficients(i).real() + dominant.coefficients(i).imag();
      for (std::size_t k = 0; k < start.size(); ++k) start[k] += weight * basis[i][k];
    }
  }
  return {std::move(ritz), std::move(basis)};
}

// The oscillator x'' = -w^2 x - c x' behind a Ritz pair: the Rayleigh quotients of J_x and J_v
// on the position part p = a + ib of its vector. For an eigenvector of the first-order system
// its eigenvalue is a root of s^2 + c s + w^2 = 0 with these (w^2, c), so an overdamped mode
// keeps its slow root: one real Ritz value alone, read as a double root, is a more damped mode
// than the cloth has (it halved symplectic Euler's predicted limit on the flag).
DampedMode mode_of(LinearisedSystem& lin, const ArnoldiResult& arnoldi,
                   const Eigen::VectorXcd& coefficients) {
  const std::size_t n = lin.vector_size();
  Vector a(n, 0.0), b(n, 0.0), image(n);
  for (Eigen::Index i = 0; i < coefficients.size(); ++i) {
    const Vector& basis = arnoldi.basis[static_cast<std::size_t>(i)];
    for (std::size_t k = 0; k < n; ++k) {
      a[k] += coefficients(i).real() * basis[k];
      b[k] += coefficients(i).imag() * basis[k];
    }
  }
  const double norm = lin.dot(a, a) + lin.dot(b, b);
  if (norm == 0.0) return {};
  auto quotient = [&](auto apply) {
    double sum = 0.0;
    for (const Vector* part : {&a, &b}) {
      apply(*part, image);
      sum += lin.dot(*part, image);
    }
    return -sum / norm;
  };
  return {
      std::max(0.0, quotient([&](const Vector& u, Vector& out) { lin.position_jacobian(u, out); })),
      std::max(0.0,
               quotient([&](const Vector& u, Vector& out) { lin.velocity_jacobian(u, out); }))};
}

}  // namespace

SpectralEstimate estimate_spectrum(const clothlab_system& system, double t,
                                   const SpectralOptions& options) {
  LinearisedSystem lin(system, t);
  SpectralEstimate estimate;
  if (lin.active_dof() == 0) return estimate;
  std::mt19937_64 random(options.seed);
  Vector scratch(lin.vector_size());
  auto stiffness = [&](const Vector& u, Vector& out) { lin.position_jacobian(u, out); };
  auto damping = [&](const Vector& u, Vector& out) { lin.velocity_jacobian(u, out); };
  auto rayleigh = [&](auto apply, const Vector& u) {
    apply(u, scratch);
    return lin.dot(u, scratch) / lin.dot(u, u);
  };

  const PowerResult stiff =
      power_iteration(lin, stiffness, random_active_vector(lin, random), options);
  const PowerResult damp =
      power_iteration(lin, damping, random_active_vector(lin, random), options);
  estimate.power_iterations_converged = stiff.converged && damp.converged;
  estimate.omega_max = std::sqrt(std::max(0.0, -stiff.rayleigh));
  estimate.stiffest_mode = {std::max(0.0, -stiff.rayleigh),
                            std::max(0.0, -rayleigh(damping, stiff.vector))};
  estimate.most_damped_mode = {std::max(0.0, -rayleigh(stiffness, damp.vector)),
                               std::max(0.0, -damp.rayleigh)};

  FirstOrderOperator op(lin);
  Vector start(2 * lin.vector_size());
  const Vector p = random_active_vector(lin, random), q = random_active_vector(lin, random);
  std::copy(p.begin(), p.end(), start.begin());
  std::copy(q.begin(), q.end(), start.begin() + static_cast<std::ptrdiff_t>(p.size()));
  const ArnoldiResult outer = arnoldi(op, std::move(start), options);
  estimate.dominant_eigenvalue = outer.ritz.front().value;
  // Only the outer part of the spectrum converges; slow modes near the origin are left out.
  const double outer_radius = 0.1 * std::abs(estimate.dominant_eigenvalue);
  for (const RitzValue& value : outer.ritz) {
    if (value.residual <= 1e-3 * std::abs(value.value) && std::abs(value.value) >= outer_radius) {
      estimate.outer_eigenvalues.push_back(value.value);
      estimate.outer_modes.push_back(mode_of(lin, outer, value.coefficients));
    }
  }
  estimate.acceleration_evaluations = lin.acceleration_evaluations();
  return estimate;
}

double predict_dt_max(Method method, const SpectralEstimate& estimate,
                      const VerletDamping& verlet) {
  if (method == Method::PositionVerlet) {
    return predicted_dt_max(method, DampedMode{estimate.stiffest_mode.omega_squared, 0.0}, verlet);
  }
  double dt_max = std::min(predicted_dt_max(method, estimate.stiffest_mode),
                           predicted_dt_max(method, estimate.most_damped_mode));
  if (method != Method::SymplecticEuler) {
    for (const Complex& eigenvalue : estimate.outer_eigenvalues) {
      // A spring-damper cloth at rest has no growing modes: a positive real part is
      // finite-difference noise on an undamped mode (or slow wind flutter), and would make
      // every method "unstable at any dt". Judge such a mode as undamped.
      const Complex passive(std::min(eigenvalue.real(), 0.0), eigenvalue.imag());
      dt_max = std::min(dt_max, predicted_dt_max(method, passive));
    }
  }
  return dt_max;
}

double predict_dt_max(const RknTable& table, const SpectralEstimate& estimate,
                      bool velocity_forces) {
  if (!velocity_forces) {
    return predicted_dt_max(table, DampedMode{estimate.stiffest_mode.omega_squared, 0.0}, false);
  }
  double dt_max = std::min(predicted_dt_max(table, estimate.stiffest_mode, true),
                           predicted_dt_max(table, estimate.most_damped_mode, true));
  for (const DampedMode& mode : estimate.outer_modes) {
    dt_max = std::min(dt_max, predicted_dt_max(table, mode, true));
  }
  return dt_max;
}

}  // namespace clothlab::analysis
