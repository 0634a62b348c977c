// A small disc offered as a triangle mesh (clothlab.mesh/1), hanging from two rim vertices,
// with a parameter that breaks the mesh or its pins: the host's wiring of meshes into the core.
#include <clothlab/ext/mesh.h>

#include <array>
#include <clothlab/sdk.hpp>
#include <cmath>
#include <cstring>
#include <numbers>
#include <string_view>
#include <vector>

namespace {

using clothlab::sdk::int_param;

struct MeshScene {
  static constexpr const char* id = "test-mesh";
  static constexpr const char* name = "Test mesh";
  static constexpr const char* version = "0.1.0";
  static constexpr const char* description =
      "a disc of triangles hanging from two rim vertices; for host tests";
  static constexpr std::array params{
      int_param("rings", 3, 1, 20, "rings of vertices around the centre (ring k has 6k)"),
      int_param("fault", 0, 0, 2, "0 none, 1 a triangle index out of range, 2 a pin past the end"),
  };

  explicit MeshScene(const clothlab::sdk::Params& values)
      : fault_(static_cast<int>(values.integer("fault"))) {
    const auto rings = static_cast<uint32_t>(values.integer("rings"));
    positions_ = {0.0, 0.0, 0.0};
    uint32_t inner_first = 0, inner_count = 1;
    for (uint32_t k = 1; k <= rings; ++k) {
      const auto outer_first = static_cast<uint32_t>(positions_.size() / 3);
      const uint32_t outer_count = 6 * k;
      for (uint32_t j = 0; j < outer_count; ++j) {
        const double angle = 2 * std::numbers::pi * j / outer_count;
        positions_.insert(positions_.end(),
                          {0.1 * k * std::cos(angle), 0.0, 0.1 * k * std::sin(angle)});
      }
      const uint32_t triangles = (inner_count > 1 ? inner_count : 0) + outer_count;
      for (uint32_t t = 0, i = 0, j = 0; t < triangles; ++t) {
        const uint32_t inner = inner_first + i % inner_count;
        const uint32_t outer = outer_first + j % outer_count;
        if (inner_count > 1 && i < inner_count &&
            (j == outer_count || uint64_t{i + 1} * outer_count < uint64_t{j + 1} * inner_count)) {
          triangles_.insert(triangles_.end(), {inner, outer, inner_first + (i + 1) % inner_count});
          ++i;
        } else {
          triangles_.insert(triangles_.end(), {inner, outer, outer_first + (j + 1) % outer_count});
          ++j;
        }
      }
      inner_first = outer_first;
      inner_count = outer_count;
    }
    const auto vertices = static_cast<uint32_t>(positions_.size() / 3);
    pinned_ = {inner_first, inner_first + inner_count / 2};  // opposite ends of the rim
    if (fault_ == 1) triangles_[4] = vertices;
    if (fault_ == 2) pinned_.push_back(vertices);
  }

  void describe(clothlab_scene& scene) const {
    scene.rows = 1;  // not read: the cloth is the mesh
    scene.cols = 1;
    scene.total_mass = 0.05;
    scene.structural = {20.0, 0.01};
    scene.shear = {10.0, 0.005};
    scene.flexion = {1.0, 0.0005};
    scene.gravity[1] = -9.81;
    scene.pinned_count = static_cast<uint32_t>(pinned_.size());
    scene.pinned = pinned_.data();
  }

  static const void* extension(std::string_view id) noexcept {
    static const clothlab_mesh_extension mesh{
        [](void* instance, clothlab_mesh* out, clothlab_message*) -> clothlab_status {
          const auto& self = *static_cast<const MeshScene*>(instance);
          if (out == nullptr || out->struct_size < CLOTHLAB_MESH_SIZE_1)
            return CLOTHLAB_ERROR_INVALID_ARGUMENT;
          out->vertex_count = static_cast<uint32_t>(self.positions_.size() / 3);
          out->triangle_count = static_cast<uint32_t>(self.triangles_.size() / 3);
          out->positions = self.positions_.data();
          out->triangles = self.triangles_.data();
          out->masses = nullptr;
          return CLOTHLAB_OK;
        }};
    return id == CLOTHLAB_EXT_MESH ? &mesh : nullptr;
  }

 private:
  int fault_;
  std::vector<double> positions_;
  std::vector<uint32_t> triangles_;
  std::vector<uint32_t> pinned_;
};

}  // namespace

CLOTHLAB_PLUGIN_ENTRY("clothlab-test-mesh", "0.1.0", clothlab::sdk::integrators<>,
                      clothlab::sdk::scenarios<MeshScene>)
