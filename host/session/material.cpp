#include "material.hpp"

#include <clothlab/core/cloth.hpp>
#include <clothlab/host/errors.hpp>
#include <cmath>
#include <cstdio>

namespace clothlab::cli {

namespace {

// The scenario parameters the material decides.
constexpr const char* decided_keys[] = {"mass",     "structural.ks", "structural.kd", "shear.ks",
                                        "shear.kd", "flexion.ks",    "flexion.kd"};

double grid_value(const host::ParamSet& params, const char* key, const Material& material) {
  for (const clothlab_param_spec& spec : params.specs())
    if (std::string_view(spec.name) == key) return params.value(key).v[0];
  throw host::InputError(material.source +
                         ": material needs a grid scenario with rows, cols, "
                         "width and height parameters; this one has no " +
                         key);
}

}  // namespace

GridSprings grid_springs(const Material& material, double rows, double cols, double width,
                         double height) {
  Scene layout;
  layout.rows = static_cast<uint32_t>(rows);
  layout.cols = static_cast<uint32_t>(cols);
  layout.width = width;
  layout.height = height;
  // A single row or column has no spacing across it: use the one it has (a single particle:
  // the width).
  const double row_spacing = rows > 1   ? layout.row_spacing()
                             : cols > 1 ? layout.column_spacing()
                                        : width;
  const double col_spacing = cols > 1 ? layout.column_spacing() : row_spacing;
  const double spacing = std::sqrt(row_spacing * col_spacing);
  GridSprings springs{};
  springs.mass = material.areal_density * width * height;
  springs.shear_ks = material.shear_stiffness;
  springs.structural_ks = material.stretch_stiffness - material.shear_stiffness;
  springs.flexion_ks = material.bending_stiffness / (spacing * spacing);
  springs.structural_kd = material.damping_time * springs.structural_ks;
  springs.shear_kd = material.damping_time * springs.shear_ks;
  springs.flexion_kd = material.damping_time * springs.flexion_ks;
  return springs;
}

void apply_material(const Material& material, const std::vector<Setting>& user_settings,
                    host::ParamSet& scenario_params) {
  for (const Setting& setting : user_settings)
    for (const char* key : decided_keys)
      if (setting.key == key)
        throw host::InputError(setting.source + ": scenario." + setting.key + " = " +
                               setting.value + " conflicts with the material set at " +
                               material.source +
                               "; allowed: a material or per-spring values, not both");
  const GridSprings springs = grid_springs(material, grid_value(scenario_params, "rows", material),
                                           grid_value(scenario_params, "cols", material),
                                           grid_value(scenario_params, "width", material),
                                           grid_value(scenario_params, "height", material));
  const std::string source = material.source + " (material " + material.name + ")";
  const std::pair<const char*, double> values[] = {{"mass", springs.mass},
                                                   {"structural.ks", springs.structural_ks},
                                                   {"structural.kd", springs.structural_kd},
                                                   {"shear.ks", springs.shear_ks},
                                                   {"shear.kd", springs.shear_kd},
                                                   {"flexion.ks", springs.flexion_ks},
                                                   {"flexion.kd", springs.flexion_kd}};
  for (const auto& [key, value] : values) {
    char text[64];
    std::snprintf(text, sizeof text, "%.17g", value);
    scenario_params.set(key, text, source);
  }
}

}  // namespace clothlab::cli
