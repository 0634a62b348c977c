#include "reference_forces.hpp"

#include <clothlab/ext/topology.h>

#include <algorithm>
#include <cmath>

namespace clothlab::reference {
namespace {

struct Neighbour {
  int row_step;
  int col_step;
  SpringFamily Scene::*family;
};

// Provot's springs as the seed lists them: structural, shear, flexion (bend).
constexpr Neighbour kNeighbours[] = {
    {0, 1, &Scene::structural}, {1, 0, &Scene::structural}, {1, 1, &Scene::shear},
    {1, -1, &Scene::shear},     {0, 2, &Scene::flexion},    {2, 0, &Scene::flexion},
};

}  // namespace

template <class Real>
ReferenceCloth<Real>::ReferenceCloth(const Scene& scene)
    : scene_(scene),
      initial_positions_(3 * std::size_t{scene.rows} * scene.cols),
      inverse_mass_(std::size_t{scene.rows} * scene.cols),
      forces_(3 * std::size_t{scene.rows} * scene.cols),
      mass_(static_cast<Real>(scene.total_mass / (static_cast<double>(scene.rows) * scene.cols))) {
  const int rows = static_cast<int>(scene.rows);
  const int cols = static_cast<int>(scene.cols);
  const double dx = scene.column_spacing();
  const double dy = scene.row_spacing();
  std::vector<double> exact(initial_positions_.size());
  for (int r = 0; r < rows; ++r) {
    for (int c = 0; c < cols; ++c) {
      for (int k = 0; k < 3; ++k) {
        exact[3 * (r * cols + c) + k] =
            scene.origin[k] + c * dx * scene.col_axis[k] + r * dy * scene.row_axis[k];
      }
    }
  }
  std::transform(exact.begin(), exact.end(), initial_positions_.begin(),
                 [](double value) { return static_cast<Real>(value); });

  for (int r = 0; r < rows; ++r) {
    for (int c = 0; c < cols; ++c) {
      for (const Neighbour& n : kNeighbours) {
        const int r2 = r + n.row_step;
        const int c2 = c + n.col_step;
        if (r2 >= rows || c2 < 0 || c2 >= cols) continue;
        const auto i = static_cast<uint32_t>(r * cols + c);
        const auto j = static_cast<uint32_t>(r2 * cols + c2);
        double squared = 0.0;
        for (int k = 0; k < 3; ++k) {
          const double d = exact[3 * j + k] - exact[3 * i + k];
          squared += d * d;
        }
        const SpringFamily& family = scene.*n.family;
        const uint8_t id = n.family == &Scene::structural ? CLOTHLAB_SPRING_STRUCTURAL
                           : n.family == &Scene::shear    ? CLOTHLAB_SPRING_SHEAR
                                                          : CLOTHLAB_SPRING_FLEXION;
        springs_.push_back({i, j, static_cast<Real>(std::sqrt(squared)),
                            static_cast<Real>(family.ks), static_cast<Real>(family.kd), id});
      }
    }
  }

  std::fill(inverse_mass_.begin(), inverse_mass_.end(), Real(1) / mass_);
  for (uint32_t pinned : scene.pinned) inverse_mass_[pinned] = 0;
}

template <class Real>
void ReferenceCloth<Real>::acceleration(const Real* x, const Real* v, Real* a) {
  std::fill(forces_.begin(), forces_.end(), Real(0));
  add_springs(x, v);
  if (scene_.has_wind()) add_wind(x);
  if (scene_.has_air()) add_air(x, v);
  to_acceleration(a);
}

template <class Real>
void ReferenceCloth<Real>::external_acceleration(const Real* x, const Real* v, Real* a) {
  std::fill(forces_.begin(), forces_.end(), Real(0));
  if (scene_.has_wind()) add_wind(x);
  if (scene_.has_air()) add_air(x, v);
  to_acceleration(a);
}

template <class Real>
void ReferenceCloth<Real>::to_acceleration(Real* a) const {
  const std::size_t n = particle_count();
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t k = 0; k < 3; ++k) {
      a[3 * i + k] = inverse_mass_[i] == 0 ? Real(0)
                                           : forces_[3 * i + k] * inverse_mass_[i] +
                                                 static_cast<Real>(scene_.gravity[k]);
    }
  }
}

template <class Real>
void ReferenceCloth<Real>::add_springs(const Real* x, const Real* v) {
  for (const Spring<Real>& s : springs_) {
    Real d[3];
    for (int k = 0; k < 3; ++k) d[k] = x[3 * s.j + k] - x[3 * s.i + k];
    const Real length = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    if (length == Real(0)) continue;
    // Hooke (seed eq. 2.7) along the spring; damping (eq. 2.8) on the closing speed.
    Real magnitude = s.ks * (length - s.rest);
    if (v != nullptr) {
      Real closing = 0;
      for (int k = 0; k < 3; ++k) closing += (v[3 * s.j + k] - v[3 * s.i + k]) * d[k];
      magnitude += s.kd * closing / length;
    }
    for (int k = 0; k < 3; ++k) {
      const Real f = magnitude * d[k] / length;
      forces_[3 * s.i + k] += f;
      forces_[3 * s.j + k] -= f;
    }
  }
}

template <class Real>
void ReferenceCloth<Real>::add_wind(const Real* x) {
  const std::size_t rows = scene_.rows;
  const std::size_t cols = scene_.cols;
  const Real strength = static_cast<Real>(scene_.wind_strength);
  Real w[3];
  for (int k = 0; k < 3; ++k) w[k] = static_cast<Real>(scene_.wind_direction[k]);
  auto triangle = [&](std::size_t p1, std::size_t p2, std::size_t p3) {
    Real e1[3], e2[3];
    for (int k = 0; k < 3; ++k) {
      e1[k] = x[3 * p2 + k] - x[3 * p1 + k];
      e2[k] = x[3 * p3 + k] - x[3 * p1 + k];
    }
    const Real normal[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                            e1[0] * e2[1] - e1[1] * e2[0]};
    const Real norm =
        std::sqrt(normal[0] * normal[0] + normal[1] * normal[1] + normal[2] * normal[2]);
    if (norm == Real(0)) return;
    const Real area = norm / 2;
    Real unit[3], along = 0;
    for (int k = 0; k < 3; ++k) {
      unit[k] = normal[k] / norm;
      along += unit[k] * w[k];
    }
    for (int k = 0; k < 3; ++k) {
      const Real share = strength * area * along * unit[k] / 3;
      forces_[3 * p1 + k] += share;
      forces_[3 * p2 + k] += share;
      forces_[3 * p3 + k] += share;
    }
  };
  for (std::size_t r = 0; r + 1 < rows; ++r) {
    for (std::size_t c = 0; c + 1 < cols; ++c) {
      const std::size_t a = r * cols + c;
      triangle(a, a + 1, a + cols);             // top-left triangle of the cell
      triangle(a + 1, a + cols + 1, a + cols);  // bottom-right triangle
    }
  }
}

// clothlab/ext/air.h as its comment states it, by angles: drag |cos| q A along u, lift
// cos sin q A along the unit vector perpendicular to u toward the normal's downstream side
// (q = density |u|^2 / 2), in double whatever Real is.
template <class Real>
void ReferenceCloth<Real>::add_air(const Real* x, const Real* v) {
  const std::size_t rows = scene_.rows;
  const std::size_t cols = scene_.cols;
  const Air& air = scene_.air;
  auto triangle = [&](std::size_t p1, std::size_t p2, std::size_t p3) {
    const std::size_t corners[3] = {p1, p2, p3};
    double e1[3], e2[3], u[3];
    for (int k = 0; k < 3; ++k) {
      e1[k] = double{x[3 * p2 + k]} - double{x[3 * p1 + k]};
      e2[k] = double{x[3 * p3 + k]} - double{x[3 * p1 + k]};
      double mean = 0;
      for (std::size_t corner : corners) mean += v == nullptr ? 0.0 : double{v[3 * corner + k]};
      u[k] = air.wind_velocity[k] - mean / 3;
    }
    const double normal[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                              e1[0] * e2[1] - e1[1] * e2[0]};
    const double norm = std::hypot(normal[0], normal[1], normal[2]);
    const double speed = std::hypot(u[0], u[1], u[2]);
    if (norm == 0.0 || speed == 0.0) return;
    const double area = norm / 2;
    double n[3], along[3], cosine = 0;
    for (int k = 0; k < 3; ++k) {
      n[k] = normal[k] / norm;
      along[k] = u[k] / speed;
      cosine += n[k] * along[k];
    }
    const double sine = std::sqrt(std::max(0.0, 1 - cosine * cosine));
    // n's part perpendicular to u has length sin: the lift's unit direction is it over sin
    // (times the sign of cos, so that the lift does not depend on which way n points).
    double lift_direction[3] = {0, 0, 0};
    if (sine > 0)
      for (int k = 0; k < 3; ++k)
        lift_direction[k] = std::copysign(1.0, cosine) * (n[k] - cosine * along[k]) / sine;
    const double pressure_area = 0.5 * air.density * speed * speed * area;
    const double drag = air.drag_coefficient * pressure_area * std::abs(cosine);
    const double lift = air.lift_coefficient * pressure_area * std::abs(cosine) * sine;
    for (int k = 0; k < 3; ++k) {
      const double force = drag * along[k] + lift * lift_direction[k];
      for (std::size_t corner : corners) forces_[3 * corner + k] += static_cast<Real>(force / 3);
    }
  };
  for (std::size_t r = 0; r + 1 < rows; ++r) {
    for (std::size_t c = 0; c + 1 < cols; ++c) {
      const std::size_t a = r * cols + c;
      triangle(a, a + 1, a + cols);
      triangle(a + 1, a + cols + 1, a + cols);
    }
  }
}

template class ReferenceCloth<float>;
template class ReferenceCloth<double>;

}  // namespace clothlab::reference
