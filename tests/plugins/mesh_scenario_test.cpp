// The mesh scenario through the host's loader: text parameters, reading with Assimp, placement,
// pin rules, the shipped meshes, and a one-line error for every kind of bad input.
#include <clothlab/ext/mesh.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <clothlab/host/errors.hpp>
#include <clothlab/host/plugin_library.hpp>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <string>
#include <vector>

namespace clothlab::test {
namespace {

namespace fs = std::filesystem;

const std::string plugin_path = CLOTHLAB_TEST_MESH_PLUGIN;
const fs::path assets = CLOTHLAB_TEST_MESH_ASSETS;

using Vec3 = std::array<double, 3>;

struct Read {
  std::vector<Vec3> positions;
  std::vector<std::array<uint32_t, 3>> triangles;
  std::vector<uint32_t> pinned;
  clothlab_scene scene{};
};

class MeshScenario : public ::testing::Test {
 protected:
  void SetUp() override {
    // The process id keeps two test runs at once (two builds, two SIMD targets) apart.
    folder_ = fs::temp_directory_path() /
              ("clothlab-mesh-" + std::to_string(getpid()) + "-" +
               std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
    fs::remove_all(folder_);
    fs::create_directories(folder_);
  }
  void TearDown() override { fs::remove_all(folder_); }

  std::string write(const std::string& name, const std::string& text) const {
    const fs::path path = folder_ / name;
    std::ofstream(path) << text;
    return path.string();
  }

  // Creates the scenario with these settings (scenario keys without the prefix) and reads its
  // scene and mesh back.
  Read read(const std::string& file,
            const std::vector<std::pair<std::string, std::string>>& settings = {}) const {
    const host::ScenarioPlugin& scenario = library_.scenario();
    host::ParamSet params = scenario.default_params();
    params.set("file", file, "--set");
    for (const auto& [key, value] : settings) params.set(key, value, "--set");
    const host::ScenarioInstance instance = scenario.create(params);
    Read out;
    out.scene = instance.describe();
    out.pinned.assign(out.scene.pinned, out.scene.pinned + out.scene.pinned_count);
    const auto* table =
        static_cast<const clothlab_mesh_extension*>(scenario.extension(CLOTHLAB_EXT_MESH));
    EXPECT_NE(table, nullptr);
    clothlab_mesh mesh{};
    mesh.struct_size = sizeof mesh;
    clothlab_message message{};
    EXPECT_EQ(table->describe(instance.get(), &mesh, &message), CLOTHLAB_OK) << message.text;
    for (uint32_t i = 0; i < mesh.vertex_count; ++i)
      out.positions.push_back(
          {mesh.positions[3 * i], mesh.positions[3 * i + 1], mesh.positions[3 * i + 2]});
    for (uint32_t t = 0; t < mesh.triangle_count; ++t)
      out.triangles.push_back(
          {mesh.triangles[3 * t], mesh.triangles[3 * t + 1], mesh.triangles[3 * t + 2]});
    EXPECT_EQ(mesh.masses, nullptr);
    return out;
  }

  // The one-line error creating the scenario gives, or "" when it succeeds.
  std::string error(const std::string& file,
                    const std::vector<std::pair<std::string, std::string>>& settings = {}) const {
    try {
      read(file, settings);
    } catch (const std::exception& e) {
      const std::string message = e.what();
      EXPECT_EQ(message.find('\n'), std::string::npos) << message;
      return message;
    }
    return "";
  }

  fs::path folder_;
  host::PluginLibrary library_ = host::PluginLibrary::load(plugin_path);
};

// Two unit quads side by side in the x-y plane: 6 vertices, 4 triangles.
const std::string two_quads =
    "v 0 0 0\nv 1 0 0\nv 2 0 0\nv 0 1 0\nv 1 1 0\nv 2 1 0\n"
    "f 1 2 5 4\nf 2 3 6 5\n";

std::multiset<Vec3> position_set(const std::vector<Vec3>& positions) {
  return {positions.begin(), positions.end()};
}

TEST_F(MeshScenario, ReadsQuadsAsTrianglesWithOneVertexPerPosition) {
  const Read mesh = read(write("quads.obj", two_quads));
  ASSERT_EQ(mesh.positions.size(), 6u);
  EXPECT_EQ(mesh.triangles.size(), 4u);
  EXPECT_EQ(
      position_set(mesh.positions),
      (std::multiset<Vec3>{{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {0, 1, 0}, {1, 1, 0}, {2, 1, 0}}));
  EXPECT_TRUE(mesh.pinned.empty());
  // The grid fields hold a valid one-row layout of the vertices for a host that checks them.
  EXPECT_EQ(mesh.scene.rows * mesh.scene.cols, 6u);
  // The same file gives the same numbering.
  const Read again = read(folder_ / "quads.obj");
  EXPECT_EQ(again.positions, mesh.positions);
  EXPECT_EQ(again.triangles, mesh.triangles);
}

TEST_F(MeshScenario, JoinsCornersAcrossGroupsAndTextureSeams) {
  // Two groups sharing the edge 2-5, each corner with its own texture coordinate.
  const Read mesh = read(write("groups.obj",
                               "v 0 0 0\nv 1 0 0\nv 2 0 0\nv 0 1 0\nv 1 1 0\nv 2 1 0\n"
                               "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
                               "g left\nf 1/1 2/2 5/3 4/4\ng right\nf 2/1 3/2 6/3 5/4\n"));
  EXPECT_EQ(mesh.positions.size(), 6u);
  EXPECT_EQ(mesh.triangles.size(), 4u);
}

TEST_F(MeshScenario, PlacesByScaleThenRotationThenTranslation) {
  const Read mesh =
      read(write("quads.obj", two_quads),
           {{"scale", "2"}, {"rotation", "[0, 90, 0]"}, {"translation", "[1, 2, 3]"}});
  // (2, 0, 0) scaled to (4, 0, 0), turned about y to (0, 0, -4), moved to (1, 2, -1).
  const auto found = std::find_if(mesh.positions.begin(), mesh.positions.end(), [](const Vec3& p) {
    return std::abs(p[0] - 1) < 1e-12 && std::abs(p[1] - 2) < 1e-12 && std::abs(p[2] + 1) < 1e-12;
  });
  EXPECT_NE(found, mesh.positions.end());
}

TEST_F(MeshScenario, PinsByBoxPlaneIndicesAndTheirUnion) {
  const std::string file = write("quads.obj", two_quads);
  const auto pinned_positions = [](const Read& mesh) {
    std::multiset<Vec3> out;
    for (uint32_t i : mesh.pinned) out.insert(mesh.positions[i]);
    return out;
  };
  const Read box = read(
      file,
      {{"pin.by_box", "true"}, {"pin.box.min", "[-1, 0.5, -1]"}, {"pin.box.max", "[1.5, 2, 1]"}});
  EXPECT_EQ(pinned_positions(box), (std::multiset<Vec3>{{0, 1, 0}, {1, 1, 0}}));
  const Read plane = read(file, {{"pin.by_plane", "true"},
                                 {"pin.plane.point", "[2, 0, 0]"},
                                 {"pin.plane.normal", "[3, 0, 0]"},
                                 {"pin.plane.distance", "0.01"}});
  EXPECT_EQ(pinned_positions(plane), (std::multiset<Vec3>{{2, 0, 0}, {2, 1, 0}}));
  const Read indices = read(file, {{"pin.indices", "0, 3"}});
  EXPECT_EQ(indices.pinned, (std::vector<uint32_t>{0, 3}));
  EXPECT_EQ(read(file, {{"pin.indices", "[0, 3]"}}).pinned, (std::vector<uint32_t>{0, 3}));
  // Vertex 0 is the first the faces use, (0, 0, 0); the plane adds the two at x = 2.
  const Read both = read(file, {{"pin.indices", "0"},
                                {"pin.by_plane", "true"},
                                {"pin.plane.point", "[2, 0, 0]"},
                                {"pin.plane.normal", "[1, 0, 0]"}});
  EXPECT_EQ(pinned_positions(both), (std::multiset<Vec3>{{0, 0, 0}, {2, 0, 0}, {2, 1, 0}}));
  EXPECT_TRUE(std::is_sorted(both.pinned.begin(), both.pinned.end()));
}

TEST_F(MeshScenario, PinsByVertexColour) {
  const std::string file = write("coloured.obj",
                                 "v 0 0 0 1 0 0\nv 1 0 0 0 0 1\nv 2 0 0 0 0 1\n"
                                 "v 0 1 0 1 0 0\nv 1 1 0 0.95 0.05 0\nv 2 1 0 0 0 1\n"
                                 "f 1 2 5 4\nf 2 3 6 5\n");
  const Read mesh = read(file, {{"pin.by_color", "true"}});
  std::multiset<Vec3> pinned;
  for (uint32_t i : mesh.pinned) pinned.insert(mesh.positions[i]);
  EXPECT_EQ(pinned, (std::multiset<Vec3>{{0, 0, 0}, {0, 1, 0}, {1, 1, 0}}));
}

// A glTF triangle with COLOR_0 (red, blue, red) and a fourth vertex, at (5, 5, 5), that no
// triangle uses (written by a script from its float32 buffers).
const std::string coloured_gltf =
    "{\"asset\":{\"version\":\"2.0\"},\"scenes\":[{\"nodes\":[0]}],\"nodes\":[{\"mesh\":0}],"
    "\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":0,\"COLOR_0\":1},\"indices\":2}]}],"
    "\"buffers\":[{\"byteLength\":104,\"uri\":\"data:application/"
    "octet-stream;base64,"
    "AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAAAACgQAAAoEAAAKBAAACAPwAAAAAAAAAAAAAAAAAAAAAAAI"
    "A/AACAPwAAAAAAAAAAAAAAAAAAAAAAAIA/"
    "AAABAAIAAAA=\"}],\"bufferViews\":[{\"buffer\":0,\"byteOffset\":0,\"byteLength\":48},{"
    "\"buffer\":0,\"byteOffset\":48,\"byteLength\":48},{\"buffer\":0,\"byteOffset\":96,"
    "\"byteLength\":6}],\"accessors\":[{\"bufferView\":0,\"componentType\":5126,\"count\":4,"
    "\"type\":\"VEC3\",\"min\":[0,0,0],\"max\":[5,5,5]},{\"bufferView\":1,\"componentType\":5126,"
    "\"count\":4,\"type\":\"VEC3\"},{\"bufferView\":2,\"componentType\":5123,\"count\":3,\"type\":"
    "\"SCALAR\"}]}";

TEST_F(MeshScenario, PinsByGltfVertexColourAndCountsUnusedVertices) {
  const std::string file = write("triangle.gltf", coloured_gltf);
  ::testing::internal::CaptureStderr();
  const Read mesh = read(file, {{"pin.by_color", "true"}});
  const std::string warnings = ::testing::internal::GetCapturedStderr();
  EXPECT_EQ(warnings,
            "clothlab: warning: " + file + ": 1 vertices no triangle uses were dropped\n");
  ASSERT_EQ(mesh.positions.size(), 3u);
  std::multiset<Vec3> pinned;
  for (uint32_t i : mesh.pinned) pinned.insert(mesh.positions[i]);
  EXPECT_EQ(pinned, (std::multiset<Vec3>{{0, 0, 0}, {0, 1, 0}}));
}

TEST_F(MeshScenario, PinRulesThatSelectNothingOrAreMalformedAreErrors) {
  const std::string file = write("quads.obj", two_quads);
  EXPECT_NE(error(file, {{"pin.by_box", "true"}, {"pin.box.min", "[5, 5, 5]"}})
                .find("pin rule scenario.pin.by_box (inside pin.box.min .. pin.box.max) selects "
                      "no vertex"),
            std::string::npos);
  EXPECT_NE(error(file, {{"pin.by_plane", "true"}, {"pin.plane.point", "[0, 7, 0]"}})
                .find("scenario.pin.by_plane"),
            std::string::npos);
  EXPECT_NE(error(file, {{"pin.by_plane", "true"}, {"pin.plane.normal", "[0, 0, 0]"}})
                .find("scenario.pin.plane.normal is zero"),
            std::string::npos);
  EXPECT_NE(error(file, {{"pin.indices", "1,x"}}).find("\"x\" is not a vertex index"),
            std::string::npos);
  EXPECT_NE(error(file, {{"pin.indices", "6"}}).find("vertex 6 is past the mesh's 6 vertices"),
            std::string::npos);
  EXPECT_NE(error(file, {{"pin.by_color", "true"}}).find("the file has none"), std::string::npos);
  EXPECT_NE(error(file, {{"pin.indices", "[]"}})
                .find("pin rule scenario.pin.indices = \"[]\" selects no vertex"),
            std::string::npos);
  EXPECT_NE(error(write("coloured.obj", "v 0 0 0 0 0 1\nv 1 0 0 0 0 1\nv 0 1 0 0 0 1\nf 1 2 3\n"),
                  {{"pin.by_color", "true"}})
                .find("scenario.pin.by_color (within pin.color.tolerance of pin.color.value) "
                      "selects no vertex"),
            std::string::npos);
}

// Each bad file or limit gives its one-line error naming the file and the problem.
TEST_F(MeshScenario, BadInputGivesOneLineErrorsNamingTheFile) {
  const std::string triangle = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
  const std::vector<std::tuple<std::string, std::string, std::string>> cases = {
      {"missing.obj", "", "no such file"},
      {"empty.obj", "", ""},
      {"only-vertices.obj", triangle, ""},
      {"degenerate.obj", triangle + "v 2 0 0\nf 1 2 3\nf 1 2 4\n", "zero area (corners 0, 1, 3"},
      {"repeated.obj", triangle + "f 1 2 3\nf 1 1 2\n", "repeat a vertex (degenerate)"},
      {"non-manifold.obj", triangle + "v 0 -1 0\nv 0 0 1\nf 1 2 3\nf 2 1 4\nf 1 2 5\n",
       "in more than two triangles (0, 1, 2): non-manifold"},
      {"winding.obj", triangle + "v 1 1 0\nf 1 2 3\nf 2 4 3\nf 1 2 4\n",
       "wind their shared edge the same way"},
      {"infinite.obj", "v 1e999 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", "(allowed: finite)"},
      {"nan.obj", "v nan 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", "coordinate x = nan (allowed: finite)"},
      {"out-of-range.obj", triangle + "f 1 2 9\n", ""},
      {"unknown.xyz", "this is no mesh\n", "No suitable reader found"},
  };
  for (const auto& [name, text, expected] : cases) {
    const std::string path = name == "missing.obj" ? (folder_ / name).string() : write(name, text);
    const std::string message = error(path);
    EXPECT_NE(message.find(path), std::string::npos) << name << ": " << message;
    EXPECT_NE(message.find(expected), std::string::npos) << name << ": " << message;
  }
}

TEST_F(MeshScenario, RefusesAFolderAnOversizedFileAndTooManyVertices) {
  EXPECT_NE(error(folder_.string()).find("is a folder"), std::string::npos);
  const std::string file = write("quads.obj", two_quads);
  // 0.001 MB = 1000 bytes, below the padded file's 2000 and more: refused before it is read.
  const std::string padded =
      write("padded.obj", std::string("#").append(1999, ' ').append("\n").append(two_quads));
  EXPECT_NE(error(padded, {{"max_file_mb", "0.001"}})
                .find(padded + ": 0.00207 MB is over the limit scenario.max_file_mb = 0.001"),
            std::string::npos)
      << error(padded, {{"max_file_mb", "0.001"}});
  EXPECT_EQ(error(padded, {{"max_file_mb", "0.003"}}), "");
  // A 1 GB file (sparse: no byte of it is written or read) against the default 256 MB.
  const std::string huge = write("huge.obj", "");
  fs::resize_file(huge, uintmax_t{1} << 30);
  EXPECT_NE(error(huge).find(huge + ": 1.07e+03 MB is over the limit scenario.max_file_mb = 256"),
            std::string::npos)
      << error(huge);
  EXPECT_NE(error(file, {{"max_vertices", "5"}})
                .find("more than 5 vertices, the limit scenario.max_vertices"),
            std::string::npos);
  EXPECT_EQ(error(file, {{"max_vertices", "6"}}), "");
}

TEST_F(MeshScenario, AHostWithoutTextParametersGetsAnErrorNotADefaultMesh) {
  const clothlab_scenario& descriptor = library_.scenario().descriptor();
  std::vector<clothlab_param_value> values(descriptor.param_count);
  for (uint32_t i = 0; i < descriptor.param_count; ++i)
    for (int k = 0; k < 3; ++k) values[i].v[k] = descriptor.params[i].default_value[k];
  void* instance = nullptr;
  clothlab_message message{};
  EXPECT_EQ(descriptor.create(values.data(), descriptor.param_count, &instance, &message),
            CLOTHLAB_ERROR_INVALID_ARGUMENT);
  EXPECT_STREQ(message.text,
               "scenario.file: empty; set scenario.file=PATH to an OBJ, glTF, PLY or FBX file");
}

TEST_F(MeshScenario, ShipsMeshesThatPassTheChecks) {
  const std::map<std::string, std::pair<size_t, size_t>> counts = {
      {"curtain.obj", {975, 1824}},        {"disc.obj", {817, 1536}},
      {"cape.obj", {640, 1178}},           {"tshirt.obj", {1200, 2320}},
      {"flag-30-quads.obj", {900, 1682}},  {"flag-30-triangles.obj", {900, 1682}},
      {"sheet-30-quads.obj", {900, 1682}}, {"sheet-30-triangles.obj", {900, 1682}}};
  for (const auto& [name, expected] : counts) {
    const Read mesh = read((assets / name).string());
    EXPECT_EQ(mesh.positions.size(), expected.first) << name;
    EXPECT_EQ(mesh.triangles.size(), expected.second) << name;
  }
}

// The grid meshes hold exactly the grid scenarios' particle positions at rows = cols = 30 and
// width = height = 0.90625 (flag: origin (0, h, 0); sheet: (-w/2, h, 0); rows go down).
TEST_F(MeshScenario, GridMeshesHoldTheGridPositionsExactly) {
  for (const std::string name : {"flag", "sheet"})
    for (const std::string form : {"quads", "triangles"}) {
      const Read mesh = read((assets / (name + "-30-" + form + ".obj")).string());
      const double side = 0.90625, spacing = side / 29;
      const double left = name == "flag" ? 0.0 : -0.5 * side;
      std::multiset<Vec3> grid;
      for (int r = 0; r < 30; ++r)
        for (int c = 0; c < 30; ++c) grid.insert({left + c * spacing, side - r * spacing, 0.0});
      EXPECT_EQ(position_set(mesh.positions), grid) << name << " " << form;
    }
}

}  // namespace
}  // namespace clothlab::test
