// The frame file formats, all written without a library:
//   .vtp  VTK XML PolyData (ParaView): points, triangles, point data velocity and stretch,
//         field data TimeValue, step and the energies; arrays as raw appended binary (no
//         encoding to spend time on, the triangles' bytes computed once per run).
//   .pvd  the ParaView collection listing the .vtp files with their times.
//   .obj  Wavefront OBJ, one file per frame (Blender's stop-motion OBJ import, Houdini).
//   .pc2  Blender / 3ds Max point cache: a header and float32 positions per frame.
#pragma once

#include <clothlab/io/frame.hpp>
#include <filesystem>
#include <ostream>
#include <string>
#include <vector>

namespace clothlab::io {

// The triangles as VTK's connectivity and offsets arrays: the same in every frame.
struct VtpTopology {
  std::vector<int32_t> connectivity, offsets;
};
VtpTopology vtp_topology(const GridMesh& mesh);

void write_vtp(std::ostream& out, const VtpTopology& topology, const Frame& frame);

// Reads a .vtp this module wrote (positions, velocities, stretch, time, step, energy, and
// the triangle count in *triangles). Throws std::runtime_error naming the file and what
// is missing.
Frame read_vtp(const std::filesystem::path& path, uint64_t* triangles = nullptr);

struct CollectionEntry {
  double time = 0;
  std::string file;  // relative to the .pvd's folder
};
void write_pvd(std::ostream& out, const std::vector<CollectionEntry>& entries);
// The entries of a .pvd (any writer's: DataSet elements with timestep and file).
std::vector<CollectionEntry> read_pvd(const std::filesystem::path& path);

void write_obj(std::ostream& out, const GridMesh& mesh, const Frame& frame);

// The PC2 header for sample_count frames of vertex_count points, one sample per frame.
void write_pc2_header(std::ostream& out, uint64_t vertex_count, uint64_t sample_count);
inline constexpr size_t pc2_header_bytes = 32;

}  // namespace clothlab::io
