// The triangle mesh builder: springs derived from the triangles (triangle_mesh.hpp states the
// rules; docs/reference/cloth-model.md says why), masses by area, the colourings (coloring.hpp).
#include <algorithm>
#include <array>
#include <clothlab/core/cloth_material.hpp>
#include <clothlab/core/triangle_mesh.hpp>
#include <cmath>
#include <stdexcept>
#include <string>

namespace clothlab {
namespace {

// Relative tolerances of the shape tests: loose enough for coordinates written with six
// significant digits (an OBJ file), tight enough that no cloth drawn by hand passes by chance.
constexpr double kRectangleTolerance = 1e-3;  // of the diagonal's length
constexpr double kStraightTolerance = 1e-4;   // 1 - cos of the angle (about 0.8 degrees)

using Point = std::array<double, 3>;

struct Geometry {
  std::span<const double> positions;
  Point at(uint32_t i) const {
    return {positions[3 * std::size_t{i}], positions[3 * std::size_t{i} + 1],
            positions[3 * std::size_t{i} + 2]};
  }
  Point direction(uint32_t from, uint32_t to) const {
    const Point p = at(from), q = at(to);
    return {q[0] - p[0], q[1] - p[1], q[2] - p[2]};
  }
  double distance(uint32_t i, uint32_t j) const {
    const Point d = direction(i, j);
    return std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
  }
};

double cosine(const Point& u, const Point& w) {
  const double uu = u[0] * u[0] + u[1] * u[1] + u[2] * u[2];
  const double ww = w[0] * w[0] + w[1] * w[1] + w[2] * w[2];
  return (u[0] * w[0] + u[1] * w[1] + u[2] * w[2]) / std::sqrt(uu * ww);
}

// Whether a, p, b, q (diagonals ab and pq) is a rectangle: diagonals of one length that halve
// each other (then the four points lie in one plane, the diagonals' plane).
bool is_rectangle(const Geometry& g, uint32_t a, uint32_t b, uint32_t p, uint32_t q) {
  const double diagonal = g.distance(a, b);
  const Point pa = g.at(a), pb = g.at(b), pp = g.at(p), pq = g.at(q);
  double apart = 0;
  for (int k = 0; k < 3; ++k) {
    const double d = (pa[k] + pb[k]) - (pp[k] + pq[k]);  // twice the midpoints' offset
    apart += d * d;
  }
  const double tolerance = kRectangleTolerance * diagonal;
  return std::sqrt(apart) <= 2 * tolerance && std::abs(g.distance(p, q) - diagonal) <= tolerance;
}

// A spring to be, with the triangles its material law reads: a structural edge's one or two, a
// shear diagonal's rectangle (none for flexion).
struct Candidate {
  uint32_t i, j;
  uint8_t family;
  uint32_t triangle_count = 0;
  std::array<uint32_t, 2> triangles{};
};

}  // namespace

std::shared_ptr<const ClothModel> build_mesh_model(const TriangleMesh& mesh, const Scene& scene,
                                                   const ClothMaterial* material) {
  const std::string reason = validate_triangle_mesh(mesh.positions, mesh.triangles, mesh.masses);
  if (!reason.empty()) throw std::invalid_argument("mesh: " + reason);
  const Geometry g{mesh.positions};
  const auto n = static_cast<uint32_t>(mesh.positions.size() / 3);
  auto model = std::make_shared<ClothModel>();
  model->particle_count = n;
  model->rest_positions = mesh.positions;
  model->triangles = mesh.triangles;

  // Edges: structural, or shear where two triangles form a rectangle split along it.
  const std::vector<sdk::mesh::EdgeUse> uses = sdk::mesh::edge_uses(mesh.triangles);
  std::vector<Candidate> candidates;
  struct SharedEdge {
    uint32_t a, b, p, q;
  };
  std::vector<SharedEdge> shared_structural;
  std::vector<std::vector<uint32_t>> structural_neighbours(n);
  std::vector<bool> sheared_half(mesh.triangles.size() / 3, false);
  for (std::size_t e = 0; e < uses.size();) {
    const bool shared = e + 1 < uses.size() && uses[e + 1].key == uses[e].key;
    const uint32_t a = uses[e].a(), b = uses[e].b();
    const uint32_t triangle_count = shared ? 2 : 1;
    const std::array<uint32_t, 2> triangles{uses[e].triangle,
                                            shared ? uses[e + 1].triangle : uses[e].triangle};
    if (shared && is_rectangle(g, a, b, uses[e].opposite, uses[e + 1].opposite)) {
      const uint32_t p = uses[e].opposite, q = uses[e + 1].opposite;
      candidates.push_back({a, b, CLOTHLAB_SPRING_SHEAR, 2, triangles});
      candidates.push_back({std::min(p, q), std::max(p, q), CLOTHLAB_SPRING_SHEAR, 2, triangles});
      sheared_half[triangles[0]] = sheared_half[triangles[1]] = true;
    } else {
      candidates.push_back({a, b, CLOTHLAB_SPRING_STRUCTURAL, triangle_count, triangles});
      structural_neighbours[a].push_back(b);
      structural_neighbours[b].push_back(a);
      if (shared) shared_structural.push_back({a, b, uses[e].opposite, uses[e + 1].opposite});
    }
    e += shared ? 2 : 1;
  }

  // Flexion along straight lines of structural edges u - v - w: each neighbour u pairs with
  // its straightest continuation w, where the pairing is mutual. line_through[v] keeps the
  // lines' directions for the cross-edge rule below.
  std::vector<std::vector<Point>> lines_through(n);
  for (uint32_t v = 0; v < n; ++v) {
    const std::vector<uint32_t>& around = structural_neighbours[v];
    auto straightest = [&](uint32_t u) {
      uint32_t best = u;
      double best_cosine = 1 - kStraightTolerance;
      for (uint32_t w : around) {
        const double c = cosine(g.direction(u, v), g.direction(v, w));
        if (w != u && c >= best_cosine) best = w, best_cosine = c;
      }
      return best;
    };
    for (uint32_t u : around) {
      const uint32_t w = straightest(u);
      if (w == u || u > w || straightest(w) != u) continue;
      candidates.push_back({u, w, CLOTHLAB_SPRING_FLEXION, 0, {}});
      lines_through[v].push_back(g.direction(u, w));
    }
  }
  // Across a shared structural edge that no line through either end crosses: the opposite
  // corners, so the hinge along the edge resists bending.
  for (const SharedEdge& edge : shared_structural) {
    const Point along = g.direction(edge.a, edge.b);
    bool crossed = false;
    for (uint32_t end : {edge.a, edge.b})
      for (const Point& line : lines_through[end])
        crossed = crossed || std::abs(cosine(line, along)) < 1 - kStraightTolerance;
    if (!crossed)
      candidates.push_back(
          {std::min(edge.p, edge.q), std::max(edge.p, edge.q), CLOTHLAB_SPRING_FLEXION, 0, {}});
  }

  // One spring per pair (structural before shear before flexion), ordered by pair.
  std::sort(candidates.begin(), candidates.end(), [](const Candidate& l, const Candidate& r) {
    if (l.i != r.i) return l.i < r.i;
    return l.j != r.j ? l.j < r.j : l.family < r.family;
  });
  const SpringFamily* laws[3] = {&scene.structural, &scene.shear, &scene.flexion};
  auto area = [&](uint32_t triangle) {
    return sdk::mesh::triangle_shape(mesh.positions,
                                     mesh.triangles.data() + 3 * std::size_t{triangle})
               .double_area /
           2;
  };
  // The spring's law: the scene's family, or the material's value for this spring's geometry.
  auto law_of = [&](const Candidate& spring, double rest) {
    if (material == nullptr) return *laws[spring.family];
    double ks = 0;
    if (spring.family == CLOTHLAB_SPRING_STRUCTURAL) {
      std::array<double, 2> loans{};
      for (uint32_t k = 0; k < spring.triangle_count; ++k)
        loans[k] =
            membrane_loan(*material, area(spring.triangles[k]), sheared_half[spring.triangles[k]]);
      ks = structural_ks(std::span(loans).first(spring.triangle_count), rest);
    } else if (spring.family == CLOTHLAB_SPRING_SHEAR) {
      ks = shear_ks(*material, area(spring.triangles[0]) + area(spring.triangles[1]), rest);
    } else {
      ks = flexion_ks(*material, rest);
    }
    return SpringFamily{ks, material->damping_time * ks};
  };
  for (std::size_t c = 0; c < candidates.size(); ++c) {
    const Candidate& spring = candidates[c];
    if (c > 0 && candidates[c - 1].i == spring.i && candidates[c - 1].j == spring.j) continue;
    const double rest = g.distance(spring.i, spring.j);
    const SpringFamily law = law_of(spring, rest);
    if (law.ks == 0.0 && law.kd == 0.0) continue;
    model->first.push_back(spring.i);
    model->second.push_back(spring.j);
    model->rest_length.push_back(rest);
    model->ks.push_back(law.ks);
    model->kd.push_back(law.kd);
    model->family.push_back(spring.family);
  }

  if (!mesh.masses.empty()) {
    model->masses = mesh.masses;
  } else {
    // A third of each triangle's area to each corner, scaled to the total mass.
    std::vector<double> area(n, 0.0);
    double total_area = 0;
    for (std::size_t t = 0; t < mesh.triangles.size() / 3; ++t) {
      const uint32_t* corner = mesh.triangles.data() + 3 * t;
      const double third = sdk::mesh::triangle_shape(mesh.positions, corner).double_area / 6;
      for (int k = 0; k < 3; ++k) area[corner[k]] += third;
      total_area += 3 * third;
    }
    model->masses.resize(n);
    for (uint32_t i = 0; i < n; ++i) model->masses[i] = scene.total_mass * area[i] / total_area;
  }
  model->inverse_masses.resize(n);
  for (uint32_t i = 0; i < n; ++i) model->inverse_masses[i] = 1.0 / model->masses[i];

  detail::build_adjacency(*model);
  detail::apply_pins(*model, scene.pinned);
  model->spring_colors =
      color_springs(model->first, model->second, model->adjacency_offsets, model->adjacent_springs);
  model->particle_colors = color_particles(model->first, model->second, model->adjacency_offsets,
                                           model->adjacent_springs);
  return model;
}

double surface_area(std::span<const double> positions, std::span<const uint32_t> triangles) {
  double twice = 0;
  for (std::size_t t = 0; t + 2 < triangles.size(); t += 3)
    twice += sdk::mesh::triangle_shape(positions, triangles.data() + t).double_area;
  return twice / 2;
}

double rest_diagonal(const Scene& scene, const ClothModel& model) {
  if (model.grid) return std::hypot(scene.width, scene.height);
  const std::vector<double>& x = model.rest_positions;
  Point low{x[0], x[1], x[2]}, high = low;
  for (std::size_t i = 0; i < x.size(); i += 3)
    for (std::size_t k = 0; k < 3; ++k) {
      low[k] = std::min(low[k], x[i + k]);
      high[k] = std::max(high[k], x[i + k]);
    }
  return std::hypot(high[0] - low[0], high[1] - low[1], high[2] - low[2]);
}

TriangleMesh mesh_from_abi(const clothlab_mesh& abi) {
  if (abi.struct_size < CLOTHLAB_MESH_SIZE_1)
    throw std::invalid_argument("mesh.struct_size = " + std::to_string(abi.struct_size) +
                                ": allowed >= " + std::to_string(CLOTHLAB_MESH_SIZE_1));
  if (abi.vertex_count > kMaxMeshParticles)
    throw std::invalid_argument("mesh.vertex_count = " + std::to_string(abi.vertex_count) +
                                ": allowed <= " + std::to_string(kMaxMeshParticles));
  if ((abi.vertex_count > 0 && abi.positions == nullptr) ||
      (abi.triangle_count > 0 && abi.triangles == nullptr))
    throw std::invalid_argument("mesh: positions or triangles NULL with a count above 0");
  TriangleMesh mesh;
  mesh.positions.assign(abi.positions, abi.positions + 3 * std::size_t{abi.vertex_count});
  mesh.triangles.assign(abi.triangles, abi.triangles + 3 * std::size_t{abi.triangle_count});
  if (abi.masses != nullptr) mesh.masses.assign(abi.masses, abi.masses + abi.vertex_count);
  return mesh;
}

}  // namespace clothlab
