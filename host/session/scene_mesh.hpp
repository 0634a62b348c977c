// The cloth a scenario describes: its clothlab.mesh/1 when it offers one, else its rows x cols
// grid; and the core's model of it.
#pragma once

#include <clothlab/core/cloth.hpp>
#include <clothlab/core/cloth_material.hpp>
#include <clothlab/core/cloth_model.hpp>
#include <clothlab/core/triangle_mesh.hpp>
#include <clothlab/host/components.hpp>
#include <memory>
#include <optional>

namespace clothlab::cli {

struct SceneCloth {
  Scene scene;
  std::optional<TriangleMesh> mesh;       // none: the scene's grid
  std::optional<ClothMaterial> material;  // none: the scene's families decide the springs

  uint32_t particle_count() const {
    return mesh ? static_cast<uint32_t>(mesh->positions.size() / 3) : scene.rows * scene.cols;
  }
};

// The scenario's scene (and mesh), checked: scene_from_abi, or mesh_scene_from_abi against its
// mesh's vertex count. A malformed scene or mesh is a PluginError naming the scenario and what
// is wrong.
SceneCloth scene_cloth(const host::ScenarioPlugin& scenario,
                       const host::ScenarioInstance& instance);

// Puts a material on the cloth (apply_material): its total mass, and its springs whatever the
// scenario's parameters say.
void put_material(SceneCloth& cloth, const ClothMaterial& material);

// The core's model of `cloth` with its scene's pins as they are now: the one place the host
// turns a scenario into springs (build_mesh_model or build_grid_model).
std::shared_ptr<const ClothModel> cloth_model(const SceneCloth& cloth);

}  // namespace clothlab::cli
