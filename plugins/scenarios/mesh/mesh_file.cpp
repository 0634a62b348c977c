#include "mesh_file.hpp"

#include <assimp/config.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <assimp/Importer.hpp>
#include <bit>
#include <clothlab/sdk/error.hpp>
#include <cstdio>
#include <filesystem>
#include <system_error>
#include <unordered_map>

namespace clothlab::builtin {

namespace {

[[noreturn]] void fail(const std::string& path, const std::string& what) {
  throw sdk::Error(CLOTHLAB_ERROR_INVALID_ARGUMENT, path + ": " + what);
}

// Refuses what is no regular file or is over the size limit, before any byte is read.
void check_file(const std::string& path, double max_megabytes) {
  namespace fs = std::filesystem;
  std::error_code error;
  const fs::file_status status = fs::status(path, error);
  if (error || !fs::exists(status)) fail(path, "no such file");
  if (fs::is_directory(status)) fail(path, "is a folder; allowed: a mesh file");
  if (!fs::is_regular_file(status)) fail(path, "is not a regular file");
  const double megabytes = static_cast<double>(fs::file_size(path, error)) / 1e6;
  if (error) fail(path, "cannot read its size: " + error.message());
  if (megabytes > max_megabytes) {
    char text[160];
    std::snprintf(text, sizeof text,
                  "%.3g MB is over the limit scenario.max_file_mb = %g (raise it to read the file)",
                  megabytes, max_megabytes);
    fail(path, text);
  }
}

// Assimp's message on one line.
std::string one_line(std::string text) {
  for (char& c : text)
    if (c == '\n' || c == '\r') c = ' ';
  while (!text.empty() && (text.back() == ' ' || text.back() == '.')) text.pop_back();
  return text;
}

// Positions compare by their bits (with -0 taken as +0), so that joining never depends on
// rounding and a non-finite coordinate survives to be reported by the geometry check.
struct PositionKey {
  std::array<uint32_t, 3> bits;
  bool operator==(const PositionKey&) const = default;
};

struct PositionHash {
  size_t operator()(const PositionKey& key) const {
    uint64_t h = 1469598103934665603ull;
    for (uint32_t b : key.bits) h = (h ^ b) * 1099511628211ull;
    return static_cast<size_t>(h);
  }
};

PositionKey key_of(const aiVector3D& p) {
  return {{std::bit_cast<uint32_t>(p.x + 0.0f), std::bit_cast<uint32_t>(p.y + 0.0f),
           std::bit_cast<uint32_t>(p.z + 0.0f)}};
}

}  // namespace

MeshFile read_mesh_file(const std::string& path, const MeshFileLimits& limits) {
  if (path.empty())
    fail("scenario.file", "empty; set scenario.file=PATH to an OBJ, glTF, PLY or FBX file");
  check_file(path, limits.max_megabytes);

  Assimp::Importer importer;
  // Only the shape matters: dropping normals, texture coordinates and materials keeps Assimp
  // from splitting the meshes by them. Corners are joined below by position alone (a UV seam
  // does not cut the cloth), not by aiProcess_JoinIdenticalVertices, which compares every
  // attribute, folds non-finite coordinates together and drops unused vertices uncounted.
  importer.SetPropertyInteger(AI_CONFIG_PP_RVC_FLAGS,
                              aiComponent_NORMALS | aiComponent_TANGENTS_AND_BITANGENTS |
                                  aiComponent_TEXCOORDS | aiComponent_BONEWEIGHTS |
                                  aiComponent_ANIMATIONS | aiComponent_TEXTURES |
                                  aiComponent_LIGHTS | aiComponent_CAMERAS | aiComponent_MATERIALS);
  importer.SetPropertyInteger(AI_CONFIG_PP_SBP_REMOVE,
                              aiPrimitiveType_POINT | aiPrimitiveType_LINE);
  const aiScene* scene = importer.ReadFile(
      path, aiProcess_RemoveComponent | aiProcess_Triangulate | aiProcess_PreTransformVertices |
                aiProcess_SortByPType | aiProcess_ValidateDataStructure);
  if (scene == nullptr) fail(path, one_line(importer.GetErrorString()));
  if ((scene->mFlags & AI_SCENE_FLAGS_INCOMPLETE) != 0 || !scene->HasMeshes())
    fail(path, "no triangles; allowed: a mesh of triangles or polygons");

  MeshFile out;
  TriangleMesh& mesh = out.mesh;
  bool any_colours = false;
  for (unsigned m = 0; m < scene->mNumMeshes; ++m)
    any_colours |= scene->mMeshes[m]->HasVertexColors(0);
  std::unordered_map<PositionKey, uint32_t, PositionHash> index_of;
  for (unsigned m = 0; m < scene->mNumMeshes; ++m) {
    const aiMesh& part = *scene->mMeshes[m];
    if ((part.mPrimitiveTypes & aiPrimitiveType_TRIANGLE) == 0) continue;
    std::vector<bool> used(part.mNumVertices, false);
    for (unsigned f = 0; f < part.mNumFaces; ++f) {
      const aiFace& face = part.mFaces[f];
      if (face.mNumIndices != 3) continue;
      std::array<uint32_t, 3> triangle{};
      for (int corner = 0; corner < 3; ++corner) {
        const unsigned source = face.mIndices[corner];
        if (source >= part.mNumVertices)
          fail(path, "face " + std::to_string(f) + " uses vertex " + std::to_string(source) +
                         " of " + std::to_string(part.mNumVertices) + " (index out of range)");
        used[source] = true;
        const aiVector3D& p = part.mVertices[source];
        const auto [it, added] =
            index_of.try_emplace(key_of(p), static_cast<uint32_t>(mesh.positions.size()));
        if (added) {
          if (mesh.positions.size() >= limits.max_vertices)
            fail(path, "more than " + std::to_string(limits.max_vertices) +
                           " vertices, the limit scenario.max_vertices (raise it to run the mesh)");
          mesh.positions.push_back({p.x, p.y, p.z});
          if (any_colours) {
            const aiColor4D c =
                part.HasVertexColors(0) ? part.mColors[0][source] : aiColor4D(-1, -1, -1, 1);
            mesh.colours.push_back({c.r, c.g, c.b});
          }
        }
        triangle[corner] = it->second;
      }
      mesh.triangles.push_back(triangle);
    }
    for (bool use : used) out.unreferenced_vertices += use ? 0 : 1;
  }
  return out;
}

}  // namespace clothlab::builtin
