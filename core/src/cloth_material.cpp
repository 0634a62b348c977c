// The material's masses and spring constants (cloth_material.hpp derives them).
#include <clothlab/core/cloth_material.hpp>
#include <cmath>
#include <numeric>

namespace clothlab {

void apply_material(Scene& scene, const ClothMaterial& material, const TriangleMesh* mesh) {
  if (mesh != nullptr) {
    scene.total_mass = material.areal_density * surface_area(mesh->positions, mesh->triangles);
    return;
  }
  scene.total_mass = material.areal_density * scene.width * scene.height;
  // A single row or column has no spacing across it: use the one it has (a single particle:
  // the width).
  const double row_spacing = scene.rows > 1   ? scene.row_spacing()
                             : scene.cols > 1 ? scene.column_spacing()
                                              : scene.width;
  const double col_spacing = scene.cols > 1 ? scene.column_spacing() : row_spacing;
  const double spacing = std::sqrt(row_spacing * col_spacing);
  scene.shear.ks = material.shear_stiffness;
  scene.structural.ks = material.stretch_stiffness - material.shear_stiffness;
  scene.flexion.ks = material.bending_stiffness / (spacing * spacing);
  for (SpringFamily* family : {&scene.structural, &scene.shear, &scene.flexion})
    family->kd = material.damping_time * family->ks;
}

double membrane_loan(const ClothMaterial& material, double triangle_area, bool sheared_half) {
  const double modulus = sheared_half ? material.stretch_stiffness - material.shear_stiffness
                                      : material.stretch_stiffness;
  return modulus * triangle_area;
}

double structural_ks(std::span<const double> loans, double rest_length) {
  const double mean =
      std::accumulate(loans.begin(), loans.end(), 0.0) / static_cast<double>(loans.size());
  return 2 * mean / (rest_length * rest_length);
}

double shear_ks(const ClothMaterial& material, double rectangle_area, double rest_length) {
  return material.shear_stiffness * 2 * rectangle_area / (rest_length * rest_length);
}

double flexion_ks(const ClothMaterial& material, double rest_length) {
  const double spacing = rest_length / 2;
  return material.bending_stiffness / (spacing * spacing);
}

}  // namespace clothlab
