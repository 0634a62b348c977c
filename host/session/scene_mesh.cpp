#include "scene_mesh.hpp"

#include <clothlab/ext/mesh.h>

#include <clothlab/host/errors.hpp>
#include <stdexcept>
#include <string>

namespace clothlab::cli {

SceneCloth scene_cloth(const host::ScenarioPlugin& scenario,
                       const host::ScenarioInstance& instance) {
  const std::string owner = "scenario " + std::string(scenario.info().id);
  SceneCloth cloth;
  try {
    const clothlab_scene described = instance.describe();
    const auto* table =
        static_cast<const clothlab_mesh_extension*>(scenario.extension(CLOTHLAB_EXT_MESH));
    if (table == nullptr) {
      cloth.scene = scene_from_abi(described);
      return cloth;
    }
    clothlab_mesh raw{};
    raw.struct_size = sizeof raw;
    clothlab_message message{};
    const clothlab_status status = table->describe(instance.get(), &raw, &message);
    if (status != CLOTHLAB_OK)
      throw host::PluginError(status, owner + ": mesh: " + host::one_line(message.text));
    cloth.mesh = mesh_from_abi(raw);
    const std::string fault =
        validate_triangle_mesh(cloth.mesh->positions, cloth.mesh->triangles, cloth.mesh->masses);
    if (!fault.empty()) throw std::invalid_argument("mesh: " + fault);
    cloth.scene = mesh_scene_from_abi(described, raw.vertex_count);
  } catch (const std::invalid_argument& error) {
    throw host::PluginError(CLOTHLAB_ERROR_INVALID_ARGUMENT,
                            owner + " described an invalid scene: " + error.what());
  }
  return cloth;
}

void put_material(SceneCloth& cloth, const ClothMaterial& material) {
  apply_material(cloth.scene, material, cloth.mesh ? &*cloth.mesh : nullptr);
  cloth.material = material;
}

std::shared_ptr<const ClothModel> cloth_model(const SceneCloth& cloth) {
  return cloth.mesh ? build_mesh_model(*cloth.mesh, cloth.scene,
                                       cloth.material ? &*cloth.material : nullptr)
                    : build_grid_model(cloth.scene);
}

}  // namespace clothlab::cli
