#include <charconv>
#include <clothlab/host/param_text.hpp>
#include <clothlab/io/frame_formats.hpp>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string_view>

namespace clothlab::io {

namespace {

// Raw appended arrays: each is a UInt64 byte count (header_type="UInt64") and the bytes, at
// its offset from the '_' that opens the AppendedData section.
using ArrayHeader = uint64_t;

void append_header(std::string& out, uint64_t bytes) {
  const auto header = static_cast<ArrayHeader>(bytes);
  out.append(reinterpret_cast<const char*>(&header), sizeof header);
}

template <class T>
std::string_view bytes_of(const std::vector<T>& values) {
  return {reinterpret_cast<const char*>(values.data()), values.size() * sizeof(T)};
}

void declare(std::string& out, const char* type, const char* name, int components,
             uint64_t offset) {
  out += "        <DataArray type=\"";
  out += type;
  out += "\" Name=\"";
  out += name;
  out += "\" NumberOfComponents=\"";
  out += std::to_string(components);
  out += "\" format=\"appended\" offset=\"";
  out += std::to_string(offset);
  out += "\"/>\n";
}

void field(std::string& out, const char* name, double value) {
  out += "      <DataArray type=\"Float64\" Name=\"";
  out += name;
  out += "\" NumberOfTuples=\"1\" format=\"ascii\">";
  out += host::format_number(value);
  out += "</DataArray>\n";
}

// Field data of `tuples` tuples of `components` numbers each.
void field_tuples(std::string& out, const char* name, std::size_t tuples, std::size_t components,
                  const std::vector<double>& values) {
  out += "      <DataArray type=\"Float64\" Name=\"";
  out += name;
  out += "\" NumberOfTuples=\"" + std::to_string(tuples) + "\" NumberOfComponents=\"" +
         std::to_string(components) + "\" format=\"ascii\">";
  for (std::size_t i = 0; i < values.size(); ++i) {
    if (i) out += ' ';
    out += host::format_number(values[i]);
  }
  out += "</DataArray>\n";
}

constexpr std::size_t kShapeFields = 8, kPoseFields = 7;

uint32_t shape_code(ColliderShape shape) {
  switch (shape) {
    case ColliderShape::Sphere:
      return CLOTHLAB_COLLIDER_SPHERE;
    case ColliderShape::Capsule:
      return CLOTHLAB_COLLIDER_CAPSULE;
    case ColliderShape::Plane:
      return CLOTHLAB_COLLIDER_PLANE;
    case ColliderShape::Box:
      return CLOTHLAB_COLLIDER_BOX;
  }
  return 0;
}

void collider_fields(std::string& out, const std::vector<Collider>& colliders) {
  if (colliders.empty()) return;
  std::vector<double> shapes, poses;
  for (const Collider& c : colliders) {
    shapes.insert(shapes.end(),
                  {static_cast<double>(shape_code(c.shape)), c.radius, c.end_radius, c.half_length,
                   c.half_extents[0], c.half_extents[1], c.half_extents[2], c.thickness});
    poses.insert(poses.end(), c.pose.position.begin(), c.pose.position.end());
    poses.insert(poses.end(), c.pose.orientation.begin(), c.pose.orientation.end());
  }
  field_tuples(out, "collider_shapes", colliders.size(), kShapeFields, shapes);
  field_tuples(out, "collider_poses", colliders.size(), kPoseFields, poses);
}

// A number the file holds, read by the host's one number parser (host::parse_real).
double number_in(std::string_view text, const std::string& what,
                 const std::filesystem::path& path) {
  const std::optional<double> value = host::parse_real(text);
  if (!value)
    throw std::runtime_error(path.string() + ": " + what + " is not a number: \"" +
                             std::string(text) + "\"");
  return *value;
}

std::string read_text(const std::filesystem::path& path) {
  std::ifstream stream(path, std::ios::binary);
  if (!stream) throw std::runtime_error(path.string() + ": cannot open");
  std::ostringstream text;
  text << stream.rdbuf();
  return text.str();
}

// The text between the DataArray named name's tags (ASCII field data).
std::string_view array_body(const std::string& text, const std::string& name,
                            const std::filesystem::path& path) {
  const size_t at = text.find("Name=\"" + name + "\"");
  if (at == std::string::npos)
    throw std::runtime_error(path.string() + ": no DataArray named " + name);
  const size_t open = text.rfind('<', at);
  const size_t begin = text.find('>', at) + 1;
  const size_t end = text.find("</DataArray>", begin);
  if (open == std::string::npos || begin == 0 || end == std::string::npos)
    throw std::runtime_error(path.string() + ": DataArray " + name + " is not closed");
  return std::string_view(text).substr(begin, end - begin);
}

// The byte count before each appended array: UInt64 in this module's files, UInt32 in the
// files of earlier versions (and VTK's default).
size_t header_bytes(const std::string& text, const std::filesystem::path& path) {
  const size_t end = text.find('>', text.find("<VTKFile"));
  const std::string_view tag = std::string_view(text).substr(0, end);
  if (tag.find("header_type=\"UInt64\"") != std::string_view::npos) return 8;
  if (tag.find("header_type=") == std::string_view::npos ||
      tag.find("header_type=\"UInt32\"") != std::string_view::npos)
    return 4;
  throw std::runtime_error(path.string() + ": header_type is neither UInt32 nor UInt64");
}

template <class T>
std::vector<T> appended_values(const std::string& text, const std::string& name,
                               const std::filesystem::path& path) {
  const size_t at = text.find("Name=\"" + name + "\"");
  const size_t tag_end = at == std::string::npos ? at : text.find('>', at);
  if (tag_end == std::string::npos)
    throw std::runtime_error(path.string() + ": no DataArray named " + name);
  const size_t offset_at = text.find("offset=\"", at);
  const size_t section = text.find("<AppendedData encoding=\"raw\">");
  const size_t base = section == std::string::npos ? section : text.find('_', section);
  if (offset_at == std::string::npos || offset_at > tag_end || base == std::string::npos)
    throw std::runtime_error(path.string() + ": DataArray " + name + " is not raw appended data");
  const size_t offset_end = text.find('"', offset_at + 8);
  const double offset =
      number_in(std::string_view(text).substr(offset_at + 8, offset_end - (offset_at + 8)),
                "the offset of DataArray " + name, path);
  if (offset < 0 || offset != std::floor(offset) || offset > static_cast<double>(text.size()))
    throw std::runtime_error(path.string() + ": DataArray " + name + " has offset " +
                             host::format_number(offset) + ", not a byte offset in the file");
  const size_t begin = base + 1 + static_cast<size_t>(offset);
  const size_t header = header_bytes(text, path);
  uint64_t bytes = 0;
  if (begin + header > text.size())
    throw std::runtime_error(path.string() + ": DataArray " + name + " is truncated");
  if (header == sizeof(uint32_t)) {
    uint32_t narrow = 0;
    std::memcpy(&narrow, text.data() + begin, sizeof narrow);
    bytes = narrow;
  } else {
    std::memcpy(&bytes, text.data() + begin, sizeof bytes);
  }
  if (bytes > text.size() - begin - header || bytes % sizeof(T) != 0)
    throw std::runtime_error(path.string() + ": DataArray " + name + " is truncated");
  std::vector<T> values(bytes / sizeof(T));
  if (bytes > 0) std::memcpy(values.data(), text.data() + begin + header, bytes);
  return values;
}

double ascii_value(const std::string& text, const std::string& name,
                   const std::filesystem::path& path) {
  return number_in(array_body(text, name, path), "DataArray " + name, path);
}

std::vector<double> ascii_values(const std::string& text, const std::string& name,
                                 const std::filesystem::path& path) {
  std::vector<double> values;
  std::istringstream words{std::string(array_body(text, name, path))};
  for (std::string word; words >> word;)
    values.push_back(number_in(word, "DataArray " + name, path));
  return values;
}

// The colliders a frame holds, checked by the core's one collider and pose validation.
std::vector<Collider> read_colliders(const std::string& text, const std::filesystem::path& path) {
  if (text.find("Name=\"collider_shapes\"") == std::string::npos) return {};
  const std::vector<double> shapes = ascii_values(text, "collider_shapes", path);
  const std::vector<double> poses = ascii_values(text, "collider_poses", path);
  const std::size_t count = shapes.size() / kShapeFields;
  if (shapes.size() != count * kShapeFields || poses.size() != count * kPoseFields)
    throw std::runtime_error(path.string() + ": collider_shapes holds " +
                             std::to_string(shapes.size()) + " numbers and collider_poses " +
                             std::to_string(poses.size()) + "; allowed 8 and 7 per collider");
  std::vector<Collider> colliders;
  for (std::size_t i = 0; i < count; ++i) {
    const double* shape = shapes.data() + i * kShapeFields;
    const double* pose = poses.data() + i * kPoseFields;
    clothlab_collider raw{};
    raw.struct_size = sizeof raw;
    raw.shape = static_cast<uint32_t>(shape[0]);
    raw.radius = shape[1];
    raw.end_radius = shape[2];
    raw.half_length = shape[3];
    for (int k = 0; k < 3; ++k) raw.half_extents[k] = shape[4 + k];
    raw.thickness = shape[7];
    clothlab_pose raw_pose{};
    for (int k = 0; k < 3; ++k) raw_pose.position[k] = pose[k];
    for (int k = 0; k < 4; ++k) raw_pose.orientation[k] = pose[3 + k];
    try {
      colliders.push_back(collider_from_abi(raw));
      colliders.back().pose = pose_from_abi(raw_pose);
    } catch (const std::invalid_argument& error) {
      throw std::runtime_error(path.string() + ": collider " + std::to_string(i) + ": " +
                               error.what());
    }
  }
  return colliders;
}

}  // namespace

VtpTopology vtp_topology(const FrameMesh& mesh) {
  // A triangle continues the strip before it when it is that strip's next triangle, else it
  // starts a strip: VTK reads points p, q, r of a strip as (p, q, r) at an even position and
  // (q, p, r) at an odd one, so that all face the same way. The core lists a column of cells
  // as one such strip: 2 * rows indices and one offset per column instead of 6 * (rows - 1)
  // and one per triangle.
  std::vector<int32_t> connectivity, offsets;
  connectivity.reserve(2 * mesh.vertex_count);
  std::size_t strip_begin = 0;
  for (std::size_t t = 0; t < mesh.triangles.size(); t += 3) {
    const auto* triangle = mesh.triangles.data() + t;
    const std::size_t length = connectivity.size() - strip_begin;
    if (length >= 3) {
      const int32_t before_last = connectivity[connectivity.size() - 2];
      const int32_t last = connectivity.back();
      const bool odd = (length - 2) % 2 == 1;
      const int32_t first = odd ? last : before_last, second = odd ? before_last : last;
      const auto continues = [&](int k) {
        return static_cast<int32_t>(triangle[k]) == first &&
               static_cast<int32_t>(triangle[(k + 1) % 3]) == second;
      };
      const int k = continues(0) ? 0 : continues(1) ? 1 : continues(2) ? 2 : -1;
      if (k >= 0) {
        connectivity.push_back(static_cast<int32_t>(triangle[(k + 2) % 3]));
        continue;
      }
      offsets.push_back(static_cast<int32_t>(connectivity.size()));
      strip_begin = connectivity.size();
    }
    for (int k = 0; k < 3; ++k) connectivity.push_back(static_cast<int32_t>(triangle[k]));
  }
  if (!connectivity.empty()) offsets.push_back(static_cast<int32_t>(connectivity.size()));
  VtpTopology topology;
  topology.strips = offsets.size();
  topology.connectivity_bytes = sizeof(ArrayHeader) + bytes_of(connectivity).size();
  append_header(topology.appended, bytes_of(connectivity).size());
  topology.appended += bytes_of(connectivity);
  append_header(topology.appended, bytes_of(offsets).size());
  topology.appended += bytes_of(offsets);
  return topology;
}

void compose_vtp(VtpFile& file, const VtpTopology& topology, const Frame& frame) {
  std::string& text = file.text;
  text.assign(
      "<?xml version=\"1.0\"?>\n"
      "<VTKFile type=\"PolyData\" version=\"1.0\" byte_order=\"LittleEndian\" "
      "header_type=\"UInt64\">\n  <PolyData>\n    <FieldData>\n");
  field(text, "TimeValue", frame.time);
  field(text, "step", static_cast<double>(frame.step));
  field(text, "energy_kinetic", frame.energy.kinetic);
  field(text, "energy_spring", frame.energy.spring);
  field(text, "energy_gravity", frame.energy.gravity);
  field(text, "energy_total", frame.energy.total());
  collider_fields(text, frame.colliders);
  text += "    </FieldData>\n    <Piece NumberOfPoints=\"";
  text += std::to_string(frame.positions.size() / 3);
  text += "\" NumberOfVerts=\"0\" NumberOfLines=\"0\" NumberOfStrips=\"";
  text += std::to_string(topology.strips);
  text += "\" NumberOfPolys=\"0\">\n      <PointData Scalars=\"stretch\" Vectors=\"velocity\">\n";
  // The frame's arrays in the order they follow the '_', then the topology's.
  const std::string_view arrays[] = {bytes_of(frame.velocities), bytes_of(frame.stretch),
                                     bytes_of(frame.positions)};
  uint64_t offset = 0;
  const auto next = [&](std::string_view array) {
    const uint64_t at = offset;
    offset += sizeof(ArrayHeader) + array.size();
    return at;
  };
  declare(text, "Float32", "velocity", 3, next(arrays[0]));
  declare(text, "Float32", "stretch", 1, next(arrays[1]));
  text += "      </PointData>\n      <Points>\n";
  declare(text, "Float32", "Points", 3, next(arrays[2]));
  text += "      </Points>\n      <Strips>\n";
  declare(text, "Int32", "connectivity", 1, offset);
  declare(text, "Int32", "offsets", 1, offset + topology.connectivity_bytes);
  text += "      </Strips>\n    </Piece>\n  </PolyData>\n  <AppendedData encoding=\"raw\">\n   _";
  // The array headers and the closing tags go after the XML in the same buffer; the pieces
  // point into it once it no longer grows.
  const size_t xml_end = text.size();
  for (const std::string_view array : arrays) append_header(text, array.size());
  const size_t tail = text.size();
  text += "\n  </AppendedData>\n</VTKFile>\n";
  const auto header = [&](size_t i) {
    return std::string_view(text).substr(xml_end + i * sizeof(ArrayHeader), sizeof(ArrayHeader));
  };
  file.pieces.assign({std::string_view(text).substr(0, xml_end), header(0), arrays[0], header(1),
                      arrays[1], header(2), arrays[2], topology.appended,
                      std::string_view(text).substr(tail)});
}

void write_vtp(std::ostream& out, const VtpTopology& topology, const Frame& frame) {
  VtpFile file;
  compose_vtp(file, topology, frame);
  for (const std::string_view piece : file.pieces)
    out.write(piece.data(), static_cast<std::streamsize>(piece.size()));
}

Frame read_vtp(const std::filesystem::path& path, std::vector<uint32_t>* triangles) {
  const std::string text = read_text(path);
  if (text.find("<VTKFile type=\"PolyData\"") == std::string::npos)
    throw std::runtime_error(path.string() + ": not a VTK XML PolyData file");
  Frame frame;
  frame.positions = appended_values<float>(text, "Points", path);
  frame.velocities = appended_values<float>(text, "velocity", path);
  frame.stretch = appended_values<float>(text, "stretch", path);
  frame.time = ascii_value(text, "TimeValue", path);
  frame.step = static_cast<uint64_t>(ascii_value(text, "step", path));
  frame.energy = {ascii_value(text, "energy_kinetic", path),
                  ascii_value(text, "energy_spring", path),
                  ascii_value(text, "energy_gravity", path)};
  frame.colliders = read_colliders(text, path);
  if (frame.velocities.size() != frame.positions.size() ||
      frame.stretch.size() * 3 != frame.positions.size())
    throw std::runtime_error(path.string() + ": point data sizes do not match the points");
  if (triangles) {
    const std::vector<int32_t> points = appended_values<int32_t>(text, "connectivity", path);
    const std::vector<int32_t> ends = appended_values<int32_t>(text, "offsets", path);
    triangles->clear();
    int32_t begin = 0;
    for (const int32_t end : ends) {
      if (end - begin < 3 || end > static_cast<int32_t>(points.size()))
        throw std::runtime_error(path.string() + ": a triangle strip of fewer than 3 points");
      for (int32_t k = begin; k + 2 < end; ++k) {
        const bool odd = (k - begin) % 2 == 1;
        for (const int32_t point :
             {points[k + (odd ? 1 : 0)], points[k + (odd ? 0 : 1)], points[k + 2]}) {
          if (point < 0 || static_cast<uint64_t>(point) >= frame.stretch.size())
            throw std::runtime_error(path.string() + ": a triangle strip names point " +
                                     std::to_string(point) + ", not one of the points");
          triangles->push_back(static_cast<uint32_t>(point));
        }
      }
      begin = end;
    }
  }
  return frame;
}

void write_pvd(std::ostream& out, const std::vector<CollectionEntry>& entries) {
  out << "<?xml version=\"1.0\"?>\n"
         "<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
         "  <Collection>\n";
  for (const CollectionEntry& entry : entries)
    out << "    <DataSet timestep=\"" << host::format_number(entry.time)
        << "\" group=\"\" part=\"0\" file=\"" << entry.file << "\"/>\n";
  out << "  </Collection>\n</VTKFile>\n";
}

namespace {

// The value of attribute `name` in one XML start tag, or nullopt when it has none.
std::optional<std::string> attribute(std::string_view element, std::string_view name) {
  const std::string key = std::string(name) + "=\"";
  for (std::size_t at = element.find(key); at != std::string_view::npos;
       at = element.find(key, at + 1)) {
    const char before = element[at - 1];  // the tag's name comes first, so at > 0
    if (before != ' ' && before != '\t' && before != '\n' && before != '\r') continue;
    const std::size_t begin = at + key.size();
    const std::size_t end = element.find('"', begin);
    if (end == std::string_view::npos) return std::nullopt;
    return std::string(element.substr(begin, end - begin));
  }
  return std::nullopt;
}

}  // namespace

std::vector<CollectionEntry> read_pvd(const std::filesystem::path& path) {
  const std::string text = read_text(path);
  std::vector<CollectionEntry> entries;
  for (std::size_t at = text.find("<DataSet"); at != std::string::npos;
       at = text.find("<DataSet", at + 1)) {
    const std::size_t end = text.find('>', at);
    const std::string element = text.substr(at, end == std::string::npos ? end : end - at + 1);
    const char after = element.size() > 8 ? element[8] : '\0';
    if (after != ' ' && after != '\t' && after != '\n' && after != '\r') continue;
    const auto time = attribute(element, "timestep");
    const auto file = attribute(element, "file");
    if (!time || !file)
      throw std::runtime_error(path.string() + ": DataSet without timestep or file: " + element);
    entries.push_back({number_in(*time, "the timestep of " + element, path), *file});
  }
  return entries;
}

void write_obj(std::ostream& out, const FrameMesh& mesh, const Frame& frame) {
  out << "# ClothLab frame " << frame.index << ", step " << frame.step
      << ", t = " << host::format_number(frame.time) << " s\no cloth\n";
  std::string line;
  char buffer[32];
  const auto append = [&](float value) {
    const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
    line += ' ';
    line.append(buffer, result.ptr);
  };
  for (uint64_t i = 0; i < mesh.vertex_count; ++i) {
    line.assign(1, 'v');
    for (int k = 0; k < 3; ++k) append(frame.positions[3 * i + k]);
    line += '\n';
    out << line;
  }
  const std::vector<uint32_t>& triangles = mesh.triangles;
  for (size_t t = 0; t < triangles.size(); t += 3)
    out << "f " << triangles[t] + 1 << ' ' << triangles[t + 1] + 1 << ' ' << triangles[t + 2] + 1
        << '\n';
}

void write_pc2_header(std::ostream& out, uint64_t vertex_count, uint64_t sample_count) {
  char header[pc2_header_bytes] = "POINTCACHE2";  // 12 bytes with the terminating zero
  const int32_t version = 1;
  const auto points = static_cast<int32_t>(vertex_count);
  const float start_frame = 0.0f, sample_rate = 1.0f;
  const auto samples = static_cast<int32_t>(sample_count);
  std::memcpy(header + 12, &version, 4);
  std::memcpy(header + 16, &points, 4);
  std::memcpy(header + 20, &start_frame, 4);
  std::memcpy(header + 24, &sample_rate, 4);
  std::memcpy(header + 28, &samples, 4);
  out.write(header, sizeof header);
}

}  // namespace clothlab::io
