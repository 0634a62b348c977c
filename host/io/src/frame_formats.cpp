#include <charconv>
#include <clothlab/host/param_text.hpp>
#include <clothlab/io/frame_formats.hpp>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <optional>
#include <regex>
#include <sstream>
#include <stdexcept>

namespace clothlab::io {

namespace {

void field(std::ostream& out, const char* name, double value) {
  out << "      <DataArray type=\"Float64\" Name=\"" << name
      << "\" NumberOfTuples=\"1\" format=\"ascii\">" << host::format_number(value)
      << "</DataArray>\n";
}

// Raw appended arrays: each is a UInt32 byte count and the bytes, at its offset from the
// '_' that opens the AppendedData section.
class AppendedArrays {
 public:
  template <class T>
  void declare(std::ostream& out, const char* type, const char* name, int components,
               const std::vector<T>& values) {
    out << "        <DataArray type=\"" << type << "\" Name=\"" << name
        << "\" NumberOfComponents=\"" << components << "\" format=\"appended\" offset=\"" << offset_
        << "\"/>\n";
    blocks_.push_back({values.data(), static_cast<uint32_t>(values.size() * sizeof(T))});
    offset_ += sizeof(uint32_t) + blocks_.back().bytes;
  }
  void write(std::ostream& out) const {
    out << "  <AppendedData encoding=\"raw\">\n   _";
    for (const Block& block : blocks_) {
      out.write(reinterpret_cast<const char*>(&block.bytes), sizeof block.bytes);
      out.write(static_cast<const char*>(block.data), block.bytes);
    }
    out << "\n  </AppendedData>\n";
  }

 private:
  struct Block {
    const void* data;
    uint32_t bytes;
  };
  std::vector<Block> blocks_;
  uint64_t offset_ = 0;
};

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
  uint32_t bytes = 0;
  if (begin + sizeof bytes > text.size())
    throw std::runtime_error(path.string() + ": DataArray " + name + " is truncated");
  std::memcpy(&bytes, text.data() + begin, sizeof bytes);
  if (begin + sizeof bytes + bytes > text.size() || bytes % sizeof(T) != 0)
    throw std::runtime_error(path.string() + ": DataArray " + name + " is truncated");
  std::vector<T> values(bytes / sizeof(T));
  if (bytes > 0) std::memcpy(values.data(), text.data() + begin + sizeof bytes, bytes);
  return values;
}

double ascii_value(const std::string& text, const std::string& name,
                   const std::filesystem::path& path) {
  return number_in(array_body(text, name, path), "DataArray " + name, path);
}

}  // namespace

VtpTopology vtp_topology(const GridMesh& mesh) {
  VtpTopology topology{mesh.triangles(), std::vector<int32_t>(mesh.triangle_count())};
  for (size_t i = 0; i < topology.offsets.size(); ++i)
    topology.offsets[i] = static_cast<int32_t>(3 * (i + 1));
  return topology;
}

void write_vtp(std::ostream& out, const VtpTopology& topology, const Frame& frame) {
  out << "<?xml version=\"1.0\"?>\n"
         "<VTKFile type=\"PolyData\" version=\"1.0\" byte_order=\"LittleEndian\" "
         "header_type=\"UInt32\">\n  <PolyData>\n    <FieldData>\n";
  field(out, "TimeValue", frame.time);
  field(out, "step", static_cast<double>(frame.step));
  field(out, "energy_kinetic", frame.energy.kinetic);
  field(out, "energy_spring", frame.energy.spring);
  field(out, "energy_gravity", frame.energy.gravity);
  field(out, "energy_total", frame.energy.total());
  out << "    </FieldData>\n    <Piece NumberOfPoints=\"" << frame.positions.size() / 3
      << "\" NumberOfVerts=\"0\" NumberOfLines=\"0\" NumberOfStrips=\"0\" NumberOfPolys=\""
      << topology.offsets.size()
      << "\">\n      <PointData Scalars=\"stretch\" Vectors=\"velocity\">\n";
  AppendedArrays arrays;
  arrays.declare(out, "Float32", "velocity", 3, frame.velocities);
  arrays.declare(out, "Float32", "stretch", 1, frame.stretch);
  out << "      </PointData>\n      <Points>\n";
  arrays.declare(out, "Float32", "Points", 3, frame.positions);
  out << "      </Points>\n      <Polys>\n";
  arrays.declare(out, "Int32", "connectivity", 1, topology.connectivity);
  arrays.declare(out, "Int32", "offsets", 1, topology.offsets);
  out << "      </Polys>\n    </Piece>\n  </PolyData>\n";
  arrays.write(out);
  out << "</VTKFile>\n";
}

Frame read_vtp(const std::filesystem::path& path, uint64_t* triangles) {
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
  if (frame.velocities.size() != frame.positions.size() ||
      frame.stretch.size() * 3 != frame.positions.size())
    throw std::runtime_error(path.string() + ": point data sizes do not match the points");
  if (triangles) *triangles = appended_values<int32_t>(text, "offsets", path).size();
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
    entries.push_back(
        {number_in(time_match[1].str(), "the timestep of " + element, path), file_match[1].str()});
  }
  return entries;
}

void write_obj(std::ostream& out, const GridMesh& mesh, const Frame& frame) {
  out << "# ClothLab frame " << frame.index << ", step " << frame.step
      << ", t = " << host::format_number(frame.time) << " s\no cloth\n";
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
