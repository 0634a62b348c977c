// A config's scenario at side x side particles in the config's material: the cotton-flag
// benches' scene (clothlab_cli_support resolves the material).
#pragma once

#include <string>

#include "bench_setup.hpp"
#include "material.hpp"
#include "run_config.hpp"

namespace clothlab::bench {

inline Scene make_material_scene(const cli::RunConfig& config, int side) {
  return make_scene(config.scenario, [&](host::ParamSet& values) {
    values.set("rows", std::to_string(side), "bench");
    values.set("cols", std::to_string(side), "bench");
    cli::apply_material(*config.material, {}, values);
  });
}

}  // namespace clothlab::bench
