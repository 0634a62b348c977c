// The area of a cloth's shadow: the union of its triangles projected onto a plane, as the
// Cusick drape test measures it (overlapping folds count once).
#pragma once

#include <array>
#include <cstdint>
#include <span>

namespace clothlab::analysis {

// positions: particle-major (x, y, z per particle); triangles: 3 indices each; normal: the
// plane's normal (any length > 0). Rasterised on a resolution x resolution grid over the
// shadow's bounding box, counting the cells whose centre some triangle covers: the error is
// below the perimeter times one cell.
double projected_area(std::span<const double> positions, std::span<const uint32_t> triangles,
                      const std::array<double, 3>& normal, int resolution = 512);

}  // namespace clothlab::analysis
