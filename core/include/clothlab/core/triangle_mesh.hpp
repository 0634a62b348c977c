// A cloth given as any triangle mesh: its validation (the one every reader calls) and the
// builder that derives the springs from the triangles (docs/reference/cloth-model.md):
//   - every edge is a structural spring, except where two triangles form a planar rectangle
//     split along its diagonal (the grid written as triangles): that diagonal and the other
//     one are shear springs;
//   - flexion springs join the ends of two structural edges that continue each other in a
//     straight line (the grid's (0,2) and (2,0));
//   - elsewhere, a shared structural edge that no such line crosses gets a flexion spring
//     between the two vertices opposite it (Jolt's default distance bend).
#pragma once

#include <clothlab/ext/mesh.h>

#include <clothlab/core/cloth.hpp>
#include <clothlab/core/cloth_model.hpp>
#include <clothlab/sdk/mesh_check.hpp>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

namespace clothlab {

inline constexpr uint32_t kMaxMeshParticles = sdk::max_mesh_particles;

struct TriangleMesh {
  std::vector<double> positions;    // 3 per vertex (m)
  std::vector<uint32_t> triangles;  // 3 vertex indices per triangle
  std::vector<double> masses;       // one per vertex (kg), or empty: total mass spread by area
};

// The one mesh check (clothlab/sdk/mesh_check.hpp: a scenario runs it too), which every reader
// and builder calls.
using sdk::validate_triangle_mesh;

// The sum of the triangles' areas (m^2): a cloth's rest area.
double surface_area(std::span<const double> positions, std::span<const uint32_t> triangles);

// A cloth's size, what errors and energy scales are measured in: a grid's diagonal,
// hypot(width, height); another cloth's the diagonal of the box around its rest positions.
double rest_diagonal(const Scene& scene, const ClothModel& model);

struct ClothMaterial;

// The model of `mesh` with the springs derived as above, ks and kd from `material` spring by
// spring (cloth_material.hpp) or, without one, from scene's families; scene.total_mass spread
// by area (unless mesh.masses), scene.pinned. Throws std::invalid_argument with
// validate_triangle_mesh's reason, or for a pin out of range.
std::shared_ptr<const ClothModel> build_mesh_model(const TriangleMesh& mesh, const Scene& scene,
                                                   const ClothMaterial* material = nullptr);

// The rows x cols sheet of a grid `scene` as an irregular mesh: each vertex moved along the two
// axes by up to a quarter of a spacing and out of the plane by up to a twentieth, each cell
// split along a diagonal, all chosen by a hash of the vertex index (so the same every time): no
// rectangles, no straight lines of edges. The mesh the conformance runner and the tests run.
TriangleMesh irregular_grid_mesh(const Scene& scene);

// A scenario's clothlab.mesh/1 (copied) as a mesh: throws std::invalid_argument naming
// "mesh.FIELD" for a short struct or a NULL array.
TriangleMesh mesh_from_abi(const clothlab_mesh& mesh);
// The scene of a scenario that offers clothlab.mesh/1: scene_from_abi's checks less the grid's
// layout (rows, cols, width, height, origin and axes are not read; rows and cols are 0), the
// pins checked against the mesh's vertex count.
Scene mesh_scene_from_abi(const clothlab_scene& scene, uint32_t vertex_count);

}  // namespace clothlab
