// A cloth read from a mesh file (OBJ, glTF, PLY, FBX through Assimp), placed by scale, rotation
// and translation, pinned by rules (a box, a plane band, a list of indices, a vertex colour),
// under gravity and the flag's wind and air. The host takes the mesh through clothlab.mesh/1 and
// derives the springs from its triangles; the spring families and the mass are the grid
// scenarios' parameters, so a material preset sets them the same way.
//
// clothlab_scene's grid fields describe no grid here (the extension says so); they hold one row
// of vertex_count particles spanning the mesh's width, a valid scene for a host that checks them.
#include <clothlab/ext/air.h>
#include <clothlab/ext/mesh.h>

#include <algorithm>
#include <array>
#include <clothlab/sdk.hpp>
#include <clothlab/sdk/text_params.hpp>
#include <cmath>
#include <cstdio>
#include <string_view>
#include <vector>

#include "../grid_cloth.hpp"
#include "../wind_and_air.hpp"
#include "mesh_file.hpp"
#include "mesh_geometry.hpp"
#include "pin_rules.hpp"
#include "placement.hpp"

namespace clothlab::builtin {

namespace {

// The particle limit's range: a 4096 x 4096 grid, the grid scenarios' largest, has as many.
constexpr double most_vertices = 4096.0 * 4096.0;

constexpr std::array mesh_placement_and_cloth_params{
    sdk::real_param("scale", 1.0, 1e-6, 1e6, "", "factor the file's coordinates are multiplied by"),
    sdk::vec3_param("rotation", {0.0, 0.0, 0.0}, -360.0, 360.0, "deg",
                    "rotation about the x, then y, then z axis, after scaling"),
    sdk::vec3_param("translation", {0.0, 0.0, 0.0}, -1e6, 1e6, "m",
                    "offset added after scaling and rotating"),
    sdk::real_param("mass", 0.3, 1e-6, 1e6, "kg", "total mass, spread by triangle area"),
    sdk::real_param("structural.ks", 20.0, 0.0, 1e9, "N/m", "stiffness of structural springs"),
    sdk::real_param("structural.kd", 0.014, 0.0, 1e6, "N s/m", "damping of structural springs"),
    sdk::real_param("shear.ks", 10.0, 0.0, 1e9, "N/m", "stiffness of shear springs"),
    sdk::real_param("shear.kd", 0.007, 0.0, 1e6, "N s/m", "damping of shear springs"),
    sdk::real_param("flexion.ks", 1.0, 0.0, 1e9, "N/m", "stiffness of flexion (bend) springs"),
    sdk::real_param("flexion.kd", 0.0007, 0.0, 1e6, "N s/m", "damping of flexion springs"),
    sdk::vec3_param("gravity", {0.0, -9.81, 0.0}, -1e3, 1e3, "m/s^2", "gravitational acceleration"),
};

constexpr std::array mesh_pin_params{
    sdk::bool_param("pin.by_box", false,
                    "pin the vertices inside the box pin.box.min .. pin.box.max"),
    sdk::vec3_param("pin.box.min", {-1e6, -1e6, -1e6}, -1e6, 1e6, "m",
                    "the pin box's lowest corner (placed coordinates)"),
    sdk::vec3_param("pin.box.max", {1e6, 1e6, 1e6}, -1e6, 1e6, "m",
                    "the pin box's highest corner (placed coordinates)"),
    sdk::bool_param("pin.by_plane", false,
                    "pin the vertices within pin.plane.distance of the plane through "
                    "pin.plane.point normal to pin.plane.normal"),
    sdk::vec3_param("pin.plane.point", {0.0, 0.0, 0.0}, -1e6, 1e6, "m",
                    "a point of the pin plane (placed coordinates)"),
    sdk::vec3_param("pin.plane.normal", {0.0, 1.0, 0.0}, -1e3, 1e3, "", "the pin plane's normal"),
    sdk::real_param("pin.plane.distance", 1e-3, 0.0, 1e6, "m",
                    "largest distance from the pin plane of a pinned vertex"),
    sdk::bool_param("pin.by_color", false,
                    "pin the vertices whose vertex colour is within pin.color.tolerance of "
                    "pin.color.value"),
    sdk::vec3_param("pin.color.value", {1.0, 0.0, 0.0}, 0.0, 1.0, "",
                    "RGB of the pinned vertices' colour"),
    sdk::real_param("pin.color.tolerance", 0.1, 0.0, 1.0, "",
                    "largest difference per channel from pin.color.value"),
    sdk::int_param("max_vertices", 1000000, 3, most_vertices,
                   "a mesh with more vertices is refused (the particle limit)"),
    sdk::real_param("max_file_mb", 256.0, 1e-3, 1e6, "MB",
                    "a larger file is refused before it is read"),
};

// Placement and cloth, then the flag's wind and air (none by default), then the pin rules and
// limits: the order --list-plugins shows.
constexpr auto mesh_params =
    concat(concat(mesh_placement_and_cloth_params, wind_and_air_params(0.0)), mesh_pin_params);

}  // namespace

struct MeshScenario {
  static constexpr const char* id = "mesh";
  static constexpr const char* name = "Mesh from a file";
  static constexpr const char* version = "1.0.0";
  static constexpr const char* description =
      "Cloth read from an OBJ, glTF, PLY or FBX file, placed and pinned by rules";
  static constexpr auto params = mesh_params;
  static constexpr std::array text_params{
      sdk::text_param("file", "", 4096, CLOTHLAB_TEXT_PATH,
                      "the mesh file (OBJ, glTF, PLY, FBX, ...); relative to the config file's "
                      "folder, or to the working directory on the command line"),
      sdk::text_param("pin.indices", "", 1 << 20, 0,
                      "vertices to pin by index, e.g. \"0,5,9\" (the scenario's vertex order)"),
  };

  // A host without clothlab.text-parameters/1: every text its default, so no file.
  explicit MeshScenario(const sdk::Params& values)
      : MeshScenario(values, sdk::TextParams(text_params)) {}

  MeshScenario(const sdk::Params& values, const sdk::TextParams& texts)
      : structural_{values.real("structural.ks"), values.real("structural.kd")},
        shear_{values.real("shear.ks"), values.real("shear.kd")},
        flexion_{values.real("flexion.ks"), values.real("flexion.kd")},
        mass_(values.real("mass")),
        gravity_(values.vec3("gravity")),
        wind_(values) {
    const std::string& path = texts.text("file");
    MeshFile file = read_mesh_file(
        path, {values.real("max_file_mb"), static_cast<uint32_t>(values.integer("max_vertices"))});
    mesh_ = std::move(file.mesh);
    check_mesh_geometry(mesh_, path);
    if (file.unreferenced_vertices > 0)
      std::fprintf(stderr, "clothlab: warning: %s: %llu vertices no triangle uses were dropped\n",
                   path.c_str(), static_cast<unsigned long long>(file.unreferenced_vertices));
    place(mesh_, {values.real("scale"), values.vec3("rotation"), values.vec3("translation")});
    check_mesh_geometry(mesh_, path + " (placed)");
    pinned_ = select_pins(mesh_, pin_rules(values, texts), path);
    for (const auto& p : mesh_.positions) positions_.insert(positions_.end(), p.begin(), p.end());
    for (const auto& t : mesh_.triangles) triangles_.insert(triangles_.end(), t.begin(), t.end());
  }

  void describe(clothlab_scene& scene) const {
    const uint32_t count = static_cast<uint32_t>(mesh_.positions.size());
    double low = mesh_.positions[0][0], high = low;
    for (const auto& p : mesh_.positions) {
      low = std::min(low, p[0]);
      high = std::max(high, p[0]);
    }
    scene.rows = 1;
    scene.cols = count;
    scene.width = std::max(high - low, 1e-3);
    scene.height = scene.width;
    set_vec3(scene.origin, low, mesh_.positions[0][1], mesh_.positions[0][2]);
    set_vec3(scene.col_axis, 1.0, 0.0, 0.0);
    set_vec3(scene.row_axis, 0.0, -1.0, 0.0);
    scene.total_mass = mass_;
    scene.structural = structural_;
    scene.shear = shear_;
    scene.flexion = flexion_;
    for (int k = 0; k < 3; ++k) scene.gravity[k] = gravity_[k];
    scene.pinned_count = static_cast<uint32_t>(pinned_.size());
    scene.pinned = pinned_.data();
    scene.wind_strength = wind_.strength;
    for (int k = 0; k < 3; ++k)
      scene.wind_direction[k] = wind_.strength > 0.0 ? wind_.direction[k] : 0.0;
  }

  clothlab_air air() const { return wind_.air; }

  static const void* extension(std::string_view extension_id) noexcept {
    static const clothlab_mesh_extension table{
        [](void* instance, clothlab_mesh* out, clothlab_message* error) -> clothlab_status {
          return sdk::guarded(error, [&] {
            if (out == nullptr || out->struct_size < CLOTHLAB_MESH_SIZE_1)
              throw sdk::Error(CLOTHLAB_ERROR_INVALID_ARGUMENT, "mesh: buffer too small");
            static_cast<const MeshScenario*>(instance)->describe_mesh(*out);
          });
        }};
    if (extension_id == CLOTHLAB_EXT_TEXT_PARAMETERS)
      return sdk::text_parameters_table<MeshScenario>();
    return extension_id == CLOTHLAB_EXT_MESH ? &table : nullptr;
  }

 private:
  static PinRules pin_rules(const sdk::Params& values, const sdk::TextParams& texts) {
    PinRules rules;
    if (values.flag("pin.by_box"))
      rules.box = BoxRule{values.vec3("pin.box.min"), values.vec3("pin.box.max")};
    if (values.flag("pin.by_plane"))
      rules.plane = PlaneRule{values.vec3("pin.plane.point"), values.vec3("pin.plane.normal"),
                              values.real("pin.plane.distance")};
    rules.indices = texts.text("pin.indices");
    if (values.flag("pin.by_color"))
      rules.colour = ColourRule{values.vec3("pin.color.value"), values.real("pin.color.tolerance")};
    return rules;
  }

  void describe_mesh(clothlab_mesh& out) const {
    out.vertex_count = static_cast<uint32_t>(mesh_.positions.size());
    out.triangle_count = static_cast<uint32_t>(mesh_.triangles.size());
    out.reserved0 = 0;
    out.positions = positions_.data();
    out.triangles = triangles_.data();
    out.masses = nullptr;
  }

  TriangleMesh mesh_;
  std::vector<double> positions_;
  std::vector<uint32_t> triangles_;
  std::vector<uint32_t> pinned_;
  clothlab_spring_family structural_, shear_, flexion_;
  double mass_;
  std::array<double, 3> gravity_;
  WindAndAir wind_;
};

}  // namespace clothlab::builtin

CLOTHLAB_PLUGIN_ENTRY("clothlab-builtin-mesh", "1.0.0", clothlab::sdk::integrators<>,
                      clothlab::sdk::scenarios<clothlab::builtin::MeshScenario>)
