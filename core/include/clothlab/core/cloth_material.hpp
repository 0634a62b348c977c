// A cloth material per unit area (independent of the mesh and its resolution) and how it becomes
// a cloth's masses and springs, on a grid and on any triangle mesh (docs/reference/cloth-model.md,
// "Material"):
//   - mass: areal density x the cloth's rest area (a grid's width x height, a mesh's triangles),
//     spread as the builder spreads mass (a grid's particles equally, a mesh's particles by a
//     third of each incident triangle's area).
//   - membrane: on a square grid of spacing h, uniform strain e along an axis stores
//     1/2 (ks_structural + ks_shear) e^2 per unit area and a shear strain g stores
//     1/2 ks_shear g^2, whatever h: so ks_shear = G and ks_structural = E - G. On a mesh each
//     triangle lends modulus x area to its edges (the modulus: E - G in a triangle that is half
//     of a rectangle whose diagonals are shear springs, they carry G; E in any other triangle),
//     and an edge's ks is twice the mean of its triangles' loans over its length squared; a
//     rectangle's diagonals get G x 2 x area / length^2. On a square cell both give the grid's
//     values; an equilateral mesh gets Young's modulus E (Poisson ratio 1/3, the only one a
//     spring network on triangles has).
//   - bending: ks_flexion = B / h^2 with h the spacing of the two edges a flexion spring spans
//     (half its rest length). A dimensional mapping, not an equivalence (a flexion spring's
//     resistance is of higher order in the bend angle), but it keeps B's effect at every spacing.
//   - damping: Rayleigh, kd = damping_time x ks, spring by spring.
#pragma once

#include <clothlab/core/cloth.hpp>
#include <clothlab/core/triangle_mesh.hpp>
#include <cstdint>
#include <span>

namespace clothlab {

struct ClothMaterial {
  double areal_density = 0;      // kg/m^2
  double stretch_stiffness = 0;  // N/m, E
  double shear_stiffness = 0;    // N/m, G (per radian of shear angle)
  double bending_stiffness = 0;  // N m, B (moment per unit width per unit curvature)
  double damping_time = 0;       // s, kd / ks
};

// Puts `material` on the cloth `scene` describes, `mesh` (or its grid when null): the total
// mass, and on a grid the three families (on a mesh build_mesh_model derives each spring's).
// Non-square grid cells use h = sqrt(h_row h_col): their membrane terms are exact only for
// square cells, as the grid has one constant per family.
void apply_material(Scene& scene, const ClothMaterial& material, const TriangleMesh* mesh);

// The per-spring laws on any mesh (the header comment says why).
double membrane_loan(const ClothMaterial& material, double triangle_area, bool sheared_half);
double structural_ks(std::span<const double> loans, double rest_length);
double shear_ks(const ClothMaterial& material, double rectangle_area, double rest_length);
double flexion_ks(const ClothMaterial& material, double rest_length);

}  // namespace clothlab
