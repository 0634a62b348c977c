#include "clothlab/analysis/projected_area.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

namespace clothlab::analysis {

namespace {

using Vec3 = std::array<double, 3>;

Vec3 cross(const Vec3& a, const Vec3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}

Vec3 unit(const Vec3& a) {
  const double length = std::hypot(a[0], a[1], a[2]);
  return {a[0] / length, a[1] / length, a[2] / length};
}

}  // namespace

double projected_area(std::span<const double> positions, std::span<const uint32_t> triangles,
                      const std::array<double, 3>& normal, int resolution) {
  const std::size_t particles = positions.size() / 3;
  if (particles == 0 || triangles.empty()) return 0;
  // Two axes spanning the plane.
  const Vec3 n = unit(normal);
  const Vec3 helper = std::abs(n[0]) < 0.9 ? Vec3{1, 0, 0} : Vec3{0, 1, 0};
  const Vec3 e1 = unit(cross(n, helper));
  const Vec3 e2 = cross(n, e1);
  std::vector<double> u(particles), w(particles);
  for (std::size_t i = 0; i < particles; ++i) {
    const double* p = &positions[3 * i];
    u[i] = p[0] * e1[0] + p[1] * e1[1] + p[2] * e1[2];
    w[i] = p[0] * e2[0] + p[1] * e2[1] + p[2] * e2[2];
  }
  const auto [u_min, u_max] = std::minmax_element(u.begin(), u.end());
  const auto [w_min, w_max] = std::minmax_element(w.begin(), w.end());
  const double u0 = *u_min, w0 = *w_min;
  const double du = (*u_max - u0) / resolution, dw = (*w_max - w0) / resolution;
  if (!(du > 0) || !(dw > 0)) return 0;  // the shadow is a segment or a point
  std::vector<uint8_t> covered(static_cast<std::size_t>(resolution) * resolution, 0);
  for (std::size_t t = 0; t + 2 < triangles.size(); t += 3) {
    const uint32_t a = triangles[t], b = triangles[t + 1], c = triangles[t + 2];
    const double det = (u[b] - u[a]) * (w[c] - w[a]) - (u[c] - u[a]) * (w[b] - w[a]);
    if (det == 0) continue;  // seen edge-on: no area of its own
    const auto cell = [](double value, double origin, double size, int limit) {
      return std::clamp(static_cast<int>((value - origin) / size), 0, limit - 1);
    };
    const int i0 = cell(std::min({u[a], u[b], u[c]}), u0, du, resolution);
    const int i1 = cell(std::max({u[a], u[b], u[c]}), u0, du, resolution);
    const int j0 = cell(std::min({w[a], w[b], w[c]}), w0, dw, resolution);
    const int j1 = cell(std::max({w[a], w[b], w[c]}), w0, dw, resolution);
    for (int j = j0; j <= j1; ++j)
      for (int i = i0; i <= i1; ++i) {
        const double pu = u0 + (i + 0.5) * du, pw = w0 + (j + 0.5) * dw;
        // Barycentric coordinates of the cell centre.
        const double beta = ((pu - u[a]) * (w[c] - w[a]) - (u[c] - u[a]) * (pw - w[a])) / det;
        const double gamma = ((u[b] - u[a]) * (pw - w[a]) - (pu - u[a]) * (w[b] - w[a])) / det;
        // A centre on an edge two triangles share rounds to just outside one or both of them.
        constexpr double edge = 1e-12;
        if (beta >= -edge && gamma >= -edge && beta + gamma <= 1 + edge)
          covered[static_cast<std::size_t>(j) * resolution + i] = 1;
      }
  }
  const auto count = std::count(covered.begin(), covered.end(), uint8_t{1});
  return static_cast<double>(count) * du * dw;
}

}  // namespace clothlab::analysis
