// The honest scenario the faulty scenario plugins start from: a sheet hanging from its two top
// corners, rows and columns as parameters, and a wind strength. Each faulty scenario changes
// one thing about it.
#pragma once

#include <array>
#include <clothlab/sdk.hpp>

namespace clothlab::faulty {

struct HangingSheetBase {
  static constexpr const char* version = "0.0.1";
  static constexpr std::array<clothlab_param_spec, 3> params{
      sdk::int_param("rows", 8, 2, 64, "particles down the sheet"),
      sdk::int_param("cols", 8, 2, 64, "particles across the sheet"),
      sdk::real_param("wind", 0.0, 0.0, 5.0, "N/m^2", "wind strength along +z")};

  explicit HangingSheetBase(const sdk::Params& values)
      : HangingSheetBase(static_cast<uint32_t>(values.integer("rows")),
                         static_cast<uint32_t>(values.integer("cols")), values.real("wind")) {}
  HangingSheetBase(uint32_t rows, uint32_t cols, double wind = 0.0)
      : rows_(rows), cols_(cols), wind_(wind), pinned_{0, cols_ - 1} {}

  void describe(clothlab_scene& scene) const {
    scene.rows = rows_;
    scene.cols = cols_;
    scene.width = 1.0;
    scene.height = 1.0;
    set(scene.origin, -0.5, 1.0, 0.0);
    set(scene.col_axis, 1.0, 0.0, 0.0);
    set(scene.row_axis, 0.0, -1.0, 0.0);
    scene.total_mass = 0.5;
    scene.structural = {40.0, 0.05};
    scene.shear = {40.0, 0.05};
    scene.flexion = {10.0, 0.02};
    set(scene.gravity, 0.0, -9.81, 0.0);
    set(scene.wind_direction, 0.0, 0.0, 1.0);
    scene.wind_strength = wind_;
    scene.pinned_count = 2;
    scene.pinned = pinned_.data();
  }

  static void set(double (&out)[3], double x, double y, double z) {
    out[0] = x;
    out[1] = y;
    out[2] = z;
  }

  uint32_t rows_, cols_;
  double wind_;
  std::array<uint32_t, 2> pinned_;
};

}  // namespace clothlab::faulty
