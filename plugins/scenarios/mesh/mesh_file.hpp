// Reading a cloth mesh from a file with Assimp (OBJ, glTF, PLY, FBX, ...).
#pragma once

#include <cstdint>
#include <string>

#include "triangle_mesh.hpp"

namespace clothlab::builtin {

struct MeshFileLimits {
  double max_megabytes;  // a larger file is refused before it is read
  uint32_t max_vertices;
};

struct MeshFile {
  TriangleMesh mesh;
  // Vertices the file holds that no triangle uses: dropped, counted for the warning.
  uint64_t unreferenced_vertices = 0;
};

// The file's triangles, every mesh of it joined into one cloth: corners at the same position
// are one vertex, numbered in the order the file's faces first use them (deterministic for a
// given file). Throws sdk::Error (invalid argument) naming the file and what is wrong.
MeshFile read_mesh_file(const std::string& path, const MeshFileLimits& limits);

}  // namespace clothlab::builtin
