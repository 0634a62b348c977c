#include <charconv>
#include <clothlab/io/frame_formats.hpp>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <regex>
#include <sstream>
#include <stdexcept>

#include "base64.hpp"

namespace clothlab::io {

namespace {

// VTK's uncompressed binary inline data: a UInt32 byte count, then the bytes, base64
// encoded as one stream.
template <class T>
std::string binary_array(const std::vector<T>& values) {
  const uint32_t bytes = static_cast<uint32_t>(values.size() * sizeof(T));
  std::string raw(sizeof bytes + bytes, '\0');
  std::memcpy(raw.data(), &bytes, sizeof bytes);
  if (bytes > 0) std::memcpy(raw.data() + sizeof bytes, values.data(), bytes);
  std::string text;
  append_base64(text, raw.data(), raw.size());
  return text;
}

std::string number_text(double value) {
  char buffer[32];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
  return std::string(buffer, result.ptr);
}

void field(std::ostream& out, const char* name, double value) {
  out << "      <DataArray type=\"Float64\" Name=\"" << name
      << "\" NumberOfTuples=\"1\" format=\"ascii\">" << number_text(value) << "</DataArray>\n";
}

void data_array(std::ostream& out, const char* type, const char* name, int components,
                const std::string& base64) {
  out << "        <DataArray type=\"" << type << "\" Name=\"" << name << "\" NumberOfComponents=\""
      << components << "\" format=\"binary\">" << base64 << "</DataArray>\n";
}

std::string read_text(const std::filesystem::path& path) {
  std::ifstream stream(path, std::ios::binary);
  if (!stream) throw std::runtime_error(path.string() + ": cannot open");
  std::ostringstream text;
  text << stream.rdbuf();
  return text.str();
}

// The body of the DataArray named name, and its opening tag.
std::string_view array_body(const std::string& text, const std::string& name,
                            const std::filesystem::path& path, std::string_view* tag = nullptr) {
  const size_t at = text.find("Name=\"" + name + "\"");
  if (at == std::string::npos)
    throw std::runtime_error(path.string() + ": no DataArray named " + name);
  const size_t open = text.rfind('<', at);
  const size_t begin = text.find('>', at) + 1;
  const size_t end = text.find("</DataArray>", begin);
  if (open == std::string::npos || begin == 0 || end == std::string::npos)
    throw std::runtime_error(path.string() + ": DataArray " + name + " is not closed");
  if (tag) *tag = std::string_view(text).substr(open, begin - open);
  return std::string_view(text).substr(begin, end - begin);
}

template <class T>
std::vector<T> binary_values(const std::string& text, const std::string& name,
                             const std::filesystem::path& path) {
  const std::vector<uint8_t> raw = decode_base64(array_body(text, name, path));
  uint32_t bytes = 0;
  if (raw.size() < sizeof bytes)
    throw std::runtime_error(path.string() + ": DataArray " + name + " has no header");
  std::memcpy(&bytes, raw.data(), sizeof bytes);
  if (raw.size() < sizeof bytes + bytes || bytes % sizeof(T) != 0)
    throw std::runtime_error(path.string() + ": DataArray " + name + " is truncated");
  std::vector<T> values(bytes / sizeof(T));
  if (bytes > 0) std::memcpy(values.data(), raw.data() + sizeof bytes, bytes);
  return values;
}

double ascii_value(const std::string& text, const std::string& name,
                   const std::filesystem::path& path) {
  const std::string body(array_body(text, name, path));
  try {
    return std::stod(body);
  } catch (const std::exception&) {
    throw std::runtime_error(path.string() + ": DataArray " + name + " is not a number");
  }
}

}  // namespace

void write_vtp(std::ostream& out, const GridMesh& mesh, const Frame& frame) {
  const std::vector<int32_t> connectivity = mesh.triangles();
  std::vector<int32_t> offsets(mesh.triangle_count());
  for (size_t i = 0; i < offsets.size(); ++i) offsets[i] = static_cast<int32_t>(3 * (i + 1));
  out << "<?xml version=\"1.0\"?>\n"
         "<VTKFile type=\"PolyData\" version=\"1.0\" byte_order=\"LittleEndian\" "
         "header_type=\"UInt32\">\n  <PolyData>\n    <FieldData>\n";
  field(out, "TimeValue", frame.time);
  field(out, "step", static_cast<double>(frame.step));
  field(out, "energy_kinetic", frame.energy.kinetic);
  field(out, "energy_spring", frame.energy.spring);
  field(out, "energy_gravity", frame.energy.gravity);
  field(out, "energy_total", frame.energy.total());
  out << "    </FieldData>\n    <Piece NumberOfPoints=\"" << mesh.vertex_count()
      << "\" NumberOfVerts=\"0\" NumberOfLines=\"0\" NumberOfStrips=\"0\" NumberOfPolys=\""
      << mesh.triangle_count()
      << "\">\n      <PointData Scalars=\"stretch\" Vectors=\"velocity\">\n";
  data_array(out, "Float32", "velocity", 3, binary_array(frame.velocities));
  data_array(out, "Float32", "stretch", 1, binary_array(frame.stretch));
  out << "      </PointData>\n      <Points>\n";
  data_array(out, "Float32", "Points", 3, binary_array(frame.positions));
  out << "      </Points>\n      <Polys>\n";
  data_array(out, "Int32", "connectivity", 1, binary_array(connectivity));
  data_array(out, "Int32", "offsets", 1, binary_array(offsets));
  out << "      </Polys>\n    </Piece>\n  </PolyData>\n</VTKFile>\n";
}

Frame read_vtp(const std::filesystem::path& path, uint64_t* triangles) {
  const std::string text = read_text(path);
  if (text.find("<VTKFile type=\"PolyData\"") == std::string::npos)
    throw std::runtime_error(path.string() + ": not a VTK XML PolyData file");
  Frame frame;
  frame.positions = binary_values<float>(text, "Points", path);
  frame.velocities = binary_values<float>(text, "velocity", path);
  frame.stretch = binary_values<float>(text, "stretch", path);
  frame.time = ascii_value(text, "TimeValue", path);
  frame.step = static_cast<uint64_t>(ascii_value(text, "step", path));
  frame.energy = {ascii_value(text, "energy_kinetic", path),
                  ascii_value(text, "energy_spring", path),
                  ascii_value(text, "energy_gravity", path)};
  if (frame.velocities.size() != frame.positions.size() ||
      frame.stretch.size() * 3 != frame.positions.size())
    throw std::runtime_error(path.string() + ": point data sizes do not match the points");
  if (triangles) *triangles = binary_values<int32_t>(text, "offsets", path).size();
  return frame;
}

void write_pvd(std::ostream& out, const std::vector<CollectionEntry>& entries) {
  out << "<?xml version=\"1.0\"?>\n"
         "<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
         "  <Collection>\n";
  for (const CollectionEntry& entry : entries)
    out << "    <DataSet timestep=\"" << number_text(entry.time)
        << "\" group=\"\" part=\"0\" file=\"" << entry.file << "\"/>\n";
  out << "  </Collection>\n</VTKFile>\n";
}

std::vector<CollectionEntry> read_pvd(const std::filesystem::path& path) {
  const std::string text = read_text(path);
  static const std::regex dataset(R"(<DataSet\s[^>]*>)");
  static const std::regex timestep(R"(timestep="([^"]*)\")");
  static const std::regex file(R"(file="([^"]*)\")");
  std::vector<CollectionEntry> entries;
  for (auto it = std::sregex_iterator(text.begin(), text.end(), dataset);
       it != std::sregex_iterator(); ++it) {
    const std::string element = it->str();
    std::smatch time_match, file_match;
    if (!std::regex_search(element, time_match, timestep) ||
        !std::regex_search(element, file_match, file))
      throw std::runtime_error(path.string() + ": DataSet without timestep or file: " + element);
    entries.push_back({std::stod(time_match[1].str()), file_match[1].str()});
  }
  return entries;
}

void write_obj(std::ostream& out, const GridMesh& mesh, const Frame& frame) {
  out << "# ClothLab frame " << frame.index << ", step " << frame.step
      << ", t = " << number_text(frame.time) << " s\no cloth\n";
  std::string line;
  char buffer[32];
  const auto append = [&](float value) {
    const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
    line += ' ';
    line.append(buffer, result.ptr);
  };
  for (uint64_t i = 0; i < mesh.vertex_count(); ++i) {
    line.assign(1, 'v');
    for (int k = 0; k < 3; ++k) append(frame.positions[3 * i + k]);
    line += '\n';
    out << line;
  }
  const std::vector<int32_t> triangles = mesh.triangles();
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
