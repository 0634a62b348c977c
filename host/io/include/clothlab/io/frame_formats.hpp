// The frame file formats, all written without a library:
//   .vtp  VTK XML PolyData (ParaView): points, the triangles as triangle strips (a grid's one
//         per column of cells, a mesh's mostly one per triangle), point data velocity and stretch,
//         field data TimeValue, step and the energies, and for a scene with colliders
//         collider_shapes (per collider: shape code of clothlab/ext/colliders.h, radius,
//         end_radius, half_length, half_extents x y z, thickness) and collider_poses (position
//         x y z, orientation w x y z), ascii; files without them (older ones) read as no
//         colliders; arrays as raw appended binary
//         (little-endian, header_type UInt64: no encoding to spend time on; the triangles'
//         bytes computed once per run and written from where they lie, as are the frame's).
//   .pvd  the ParaView collection listing the .vtp files with their times.
//   .obj  Wavefront OBJ, one file per frame (Blender's stop-motion OBJ import, Houdini).
//   .pc2  Blender / 3ds Max point cache: a header and float32 positions per frame.
#pragma once

#include <clothlab/io/frame.hpp>
#include <filesystem>
#include <ostream>
#include <string>
#include <string_view>
#include <vector>

namespace clothlab::io {

// The mesh's triangles as triangle strips, each triangle continuing the strip before it where it
// can (a grid: one strip per column of cells, a quarter of the bytes of separate triangles), VTK's
// connectivity and offsets arrays, the same in every frame: their appended bytes (each array's
// UInt64 byte count, then the Int32 values).
struct VtpTopology {
  uint64_t strips = 0;
  uint64_t connectivity_bytes = 0;  // the connectivity's count and values: where offsets starts
  std::string appended;
};
VtpTopology vtp_topology(const FrameMesh& mesh);

// A frame's .vtp as the pieces of memory it is made of, for io::write_file_atomically: the
// XML and the arrays' byte counts (in `text`), the frame's arrays and the topology's bytes.
// The pieces point into text, frame and topology, which must outlive them.
struct VtpFile {
  std::string text;
  std::vector<std::string_view> pieces;
};
void compose_vtp(VtpFile& file, const VtpTopology& topology, const Frame& frame);
void write_vtp(std::ostream& out, const VtpTopology& topology, const Frame& frame);

// Reads a .vtp this module wrote (positions, velocities, stretch, time, step, energy,
// colliders, and the triangles its strips hold in *triangles, 3 point indices each). Throws
// std::runtime_error naming the file and what is missing or malformed.
Frame read_vtp(const std::filesystem::path& path, std::vector<uint32_t>* triangles = nullptr);

struct CollectionEntry {
  double time = 0;
  std::string file;  // relative to the .pvd's folder
};
void write_pvd(std::ostream& out, const std::vector<CollectionEntry>& entries);
// The entries of a .pvd (any writer's: DataSet elements with timestep and file).
std::vector<CollectionEntry> read_pvd(const std::filesystem::path& path);

void write_obj(std::ostream& out, const FrameMesh& mesh, const Frame& frame);

// The PC2 header for sample_count frames of vertex_count points, one sample per frame.
void write_pc2_header(std::ostream& out, uint64_t vertex_count, uint64_t sample_count);
inline constexpr size_t pc2_header_bytes = 32;

}  // namespace clothlab::io
