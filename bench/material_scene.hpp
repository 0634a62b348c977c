// A config's scenario at side x side particles in the config's material: the cotton-flag
// benches' scene (clothlab_cli_support resolves the material; the core applies it).
#pragma once

#include <string>

#include "bench_setup.hpp"
#include "material.hpp"
#include "run_config.hpp"

namespace clothlab::bench {

inline Scene make_material_scene(const cli::RunConfig& config, int side) {
  Scene scene = make_scene(config.scenario, [&](host::ParamSet& values) {
    values.set("rows", std::to_string(side), "bench");
    values.set("cols", std::to_string(side), "bench");
  });
  apply_material(scene, *config.material, nullptr);
  return scene;
}

}  // namespace clothlab::bench
