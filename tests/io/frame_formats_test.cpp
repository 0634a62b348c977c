#include <gtest/gtest.h>

#include <algorithm>
#include <clothlab/io/base64.hpp>
#include <clothlab/io/frame_formats.hpp>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>

namespace clothlab::io {
namespace {

namespace fs = std::filesystem;

// The frame mesh of a rows x cols grid with its rows and columns 1 m apart.
FrameMesh grid_frame_mesh(uint32_t rows, uint32_t cols) {
  Scene scene;
  scene.rows = rows;
  scene.cols = cols;
  scene.width = cols - 1.0;
  scene.height = rows - 1.0;
  scene.structural.ks = 1;
  return FrameMesh(*build_grid_model(scene));
}

TEST(Base64, MatchesRfc4648Vectors) {
  const std::pair<const char*, const char*> vectors[] = {
      {"", ""}, {"f", "Zg=="}, {"fo", "Zm8="}, {"foo", "Zm9v"}, {"foobar", "Zm9vYmFy"}};
  for (const auto& [plain, encoded] : vectors) {
    std::string text;
    append_base64(text, plain, std::strlen(plain));
    EXPECT_EQ(text, encoded);
    const std::vector<uint8_t> decoded = decode_base64(encoded);
    EXPECT_EQ(std::string(decoded.begin(), decoded.end()), plain);
  }
  EXPECT_THROW(decode_base64("Zm9v!"), std::invalid_argument);
}

// The core's triangles (clothlab::grid_triangles), which the wind acts on: counter-clockwise
// about col_axis x row_axis. The writers used to turn them the other way.
TEST(FrameMesh, TwoTrianglesPerCellFacingAsTheWindsNormals) {
  const FrameMesh mesh = grid_frame_mesh(3, 4);
  const std::vector<uint32_t>& triangles = mesh.triangles;
  ASSERT_EQ(triangles.size(), 3 * mesh.triangle_count());
  EXPECT_EQ(mesh.triangle_count(), 12u);
  // Layout: column c at x = c, row r at y = -r: col_axis x row_axis is -z.
  for (size_t t = 0; t < triangles.size(); t += 3) {
    const auto xy = [&](uint32_t i) { return std::pair<double, double>(i % 4, -(i / 4.0)); };
    const auto [ax, ay] = xy(triangles[t]);
    const auto [bx, by] = xy(triangles[t + 1]);
    const auto [cx, cy] = xy(triangles[t + 2]);
    EXPECT_LT((bx - ax) * (cy - ay) - (by - ay) * (cx - ax), 0) << "triangle " << t / 3;
  }
}

TEST(FrameMesh, StretchIsTheLongestAdjacentStructuralSpring) {
  const FrameMesh mesh = grid_frame_mesh(2, 3);
  // Rest spacing 1 in both directions; the right column is pulled to x = 4 (spring 2x rest).
  std::vector<float> positions = {0, 0, 0, 1, 0, 0, 3, 0, 0, 0, -1, 0, 1, -1, 0, 3, -1, 0};
  std::vector<float> stretch;
  compute_stretch(mesh, positions, stretch);
  EXPECT_EQ(stretch, (std::vector<float>{1, 2, 2, 1, 2, 2}));
}

TEST(VtkPolyData, ReadsBackWhatItWrote) {
  const FrameMesh mesh = grid_frame_mesh(2, 2);
  Frame frame;
  frame.index = 3;
  frame.step = 120;
  frame.time = 0.12;
  frame.positions = {0, 0, 0, 1, 0, 0, 0, -1, 0, 1.5f, -1, 0.25f};
  frame.velocities = {0, 0, 0, 0, -1, 0, 0, 0, 2, 3, 0, 0};
  frame.stretch = {1, 1.5f, 1, 1.5f};
  frame.energy = {1.25, 0.5, -2};
  const fs::path path = fs::path(testing::TempDir()) / "frame_formats_test.vtp";
  {
    std::ofstream out(path);
    write_vtp(out, vtp_topology(mesh), frame);
  }
  std::vector<uint32_t> triangles;
  const Frame read = read_vtp(path, &triangles);
  EXPECT_EQ(read.positions, frame.positions);
  EXPECT_EQ(read.velocities, frame.velocities);
  EXPECT_EQ(read.stretch, frame.stretch);
  EXPECT_EQ(read.step, 120u);
  EXPECT_DOUBLE_EQ(read.time, 0.12);
  EXPECT_DOUBLE_EQ(read.energy.kinetic, 1.25);
  EXPECT_DOUBLE_EQ(read.energy.gravity, -2);
  EXPECT_EQ(triangles.size(), 6u);
  fs::remove(path);
}

// Every shape with its pose comes back exactly (17 significant digits); a frame without
// colliders, as every file before them, reads as none; a malformed one is one line naming the
// file, the collider and the field.
TEST(VtkPolyData, CollidersRoundTripWithTheirPoses) {
  const FrameMesh mesh = grid_frame_mesh(2, 2);
  Frame frame;
  frame.positions = {0, 0, 0, 1, 0, 0, 0, -1, 0, 1, -1, 0};
  frame.velocities.assign(12, 0.0f);
  frame.stretch.assign(4, 1.0f);
  Collider sphere;
  sphere.radius = 0.3;
  sphere.thickness = 0.005;
  sphere.pose.position = {0, -0.3, 0.1};
  Collider capsule;
  capsule.shape = ColliderShape::Capsule;
  capsule.radius = 0.12;
  capsule.end_radius = 0.07;
  capsule.half_length = 0.2;
  capsule.pose.position = {1.0 / 3, 2, -0.5};
  capsule.pose.orientation = {std::sqrt(0.5), 0, std::sqrt(0.5), 0};
  Collider plane;
  plane.shape = ColliderShape::Plane;
  Collider box;
  box.shape = ColliderShape::Box;
  box.half_extents = {0.3, 0.2, 0.1};
  frame.colliders = {sphere, capsule, plane, box};
  const fs::path path = fs::path(testing::TempDir()) / "frame_colliders_test.vtp";
  {
    std::ofstream out(path);
    write_vtp(out, vtp_topology(mesh), frame);
  }
  const Frame read = read_vtp(path);
  ASSERT_EQ(read.colliders.size(), 4u);
  for (std::size_t i = 0; i < 4; ++i) {
    const Collider &a = frame.colliders[i], &b = read.colliders[i];
    EXPECT_EQ(a.shape, b.shape) << i;
    EXPECT_EQ(a.radius, b.radius) << i;
    EXPECT_EQ(a.end_radius, b.end_radius) << i;
    EXPECT_EQ(a.half_length, b.half_length) << i;
    EXPECT_EQ(a.half_extents, b.half_extents) << i;
    EXPECT_EQ(a.thickness, b.thickness) << i;
    EXPECT_EQ(a.pose.position, b.pose.position) << i;
    for (int k = 0; k < 4; ++k)
      EXPECT_NEAR(a.pose.orientation[k], b.pose.orientation[k], 1e-15) << i;
  }

  frame.colliders.clear();
  {
    std::ofstream out(path);
    write_vtp(out, vtp_topology(mesh), frame);
  }
  EXPECT_TRUE(read_vtp(path).colliders.empty());

  frame.colliders = {capsule};
  std::ostringstream text;
  write_vtp(text, vtp_topology(mesh), frame);
  std::string broken = text.str();
  const std::string radius = " 0.12 ";
  ASSERT_NE(broken.find(radius), std::string::npos);
  broken.replace(broken.find(radius), radius.size(), " -0.12 ");
  {
    std::ofstream out(path, std::ios::binary);
    out << broken;
  }
  try {
    read_vtp(path);
    ADD_FAILURE() << "a negative radius was read";
  } catch (const std::runtime_error& error) {
    EXPECT_EQ(std::string(error.what()),
              path.string() + ": collider 0: radius = -0.12, allowed finite > 0");
  }
  fs::remove(path);
}

// The arrays are the float32 bits as the writer thread had them: values that a decimal
// text format would have to round-trip exactly (subnormals, -0, the neighbours of 1, the
// largest float) come back bit for bit, and the file says it is raw appended binary with
// UInt64 headers, which is what ParaView's reader needs to be told.
TEST(VtkPolyData, Float32ArraysRoundTripBitForBit) {
  const FrameMesh mesh = grid_frame_mesh(3, 4);
  Frame frame;
  const float awkward[] = {std::numeric_limits<float>::denorm_min(),
                           -0.0f,
                           std::nextafter(1.0f, 2.0f),
                           std::nextafter(1.0f, 0.0f),
                           std::numeric_limits<float>::max(),
                           -std::numeric_limits<float>::min(),
                           0.1f,
                           1e-30f};
  for (uint64_t i = 0; i < 3 * mesh.vertex_count; ++i) {
    frame.positions.push_back(awkward[i % 8] * static_cast<float>(i + 1));
    frame.velocities.push_back(awkward[(i + 3) % 8]);
  }
  for (uint64_t i = 0; i < mesh.vertex_count; ++i) frame.stretch.push_back(awkward[i % 8]);
  const fs::path path = fs::path(testing::TempDir()) / "frame_formats_bits.vtp";
  {
    std::ofstream out(path, std::ios::binary);
    write_vtp(out, vtp_topology(mesh), frame);
  }
  std::vector<uint32_t> triangles;
  const Frame read = read_vtp(path, &triangles);
  const auto same_bits = [](const std::vector<float>& a, const std::vector<float>& b) {
    return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(float)) == 0;
  };
  EXPECT_TRUE(same_bits(read.positions, frame.positions));
  EXPECT_TRUE(same_bits(read.velocities, frame.velocities));
  EXPECT_TRUE(same_bits(read.stretch, frame.stretch));
  EXPECT_EQ(triangles.size(), 3 * mesh.triangle_count());
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  EXPECT_NE(text.str().find("byte_order=\"LittleEndian\" header_type=\"UInt64\""),
            std::string::npos);
  EXPECT_NE(text.str().find("<AppendedData encoding=\"raw\">\n   _"), std::string::npos);
  EXPECT_NE(text.str().find("NumberOfStrips=\"3\" NumberOfPolys=\"0\""), std::string::npos);
  fs::remove(path);
}

// The same triangle turned to start at its least index: a strip hands VTK every other
// triangle from another corner.
std::vector<uint32_t> least_first(const std::vector<uint32_t>& triangles) {
  std::vector<uint32_t> out;
  for (size_t t = 0; t < triangles.size(); t += 3) {
    const auto* p = triangles.data() + t;
    const size_t k = std::min_element(p, p + 3) - p;
    out.insert(out.end(), {p[k], p[(k + 1) % 3], p[(k + 2) % 3]});
  }
  return out;
}

// One strip per column of cells: the connectivity VTK decomposes into the mesh's triangles,
// and read_vtp decomposes it the same way.
TEST(VtkPolyData, StripsHoldTheGridsTriangles) {
  const FrameMesh mesh = grid_frame_mesh(3, 3);
  const VtpTopology topology = vtp_topology(mesh);
  ASSERT_EQ(topology.strips, 2u);
  std::vector<int32_t> connectivity((topology.connectivity_bytes - 8) / 4);
  std::memcpy(connectivity.data(), topology.appended.data() + 8, connectivity.size() * 4);
  EXPECT_EQ(connectivity, (std::vector<int32_t>{0, 1, 3, 4, 6, 7, 1, 2, 4, 5, 7, 8}));
  // vtkTriangleStrip: triangle k is points k, k+1, k+2, every odd one with its first two
  // swapped so that all face the same way.
  std::vector<uint32_t> decomposed;
  for (size_t strip = 0; strip < 2; ++strip)
    for (size_t k = 0; k + 2 < 6; ++k) {
      const int32_t* p = connectivity.data() + 6 * strip + k;
      const auto at = [&](size_t i) { return static_cast<uint32_t>(p[i]); };
      if (k % 2 == 0)
        decomposed.insert(decomposed.end(), {at(0), at(1), at(2)});
      else
        decomposed.insert(decomposed.end(), {at(1), at(0), at(2)});
    }
  EXPECT_EQ(least_first(decomposed), least_first(mesh.triangles));

  Frame frame;
  frame.positions.assign(3 * mesh.vertex_count, 0.0f);
  frame.velocities = frame.positions;
  frame.stretch.assign(mesh.vertex_count, 1.0f);
  const fs::path path = fs::path(testing::TempDir()) / "frame_formats_strips.vtp";
  {
    std::ofstream out(path, std::ios::binary);
    write_vtp(out, topology, frame);
  }
  std::vector<uint32_t> read;
  read_vtp(path, &read);
  EXPECT_EQ(read, decomposed);
  fs::remove(path);
}

// Frames of the earlier version (UInt32 array headers) still read: a viewer pointed at them.
TEST(VtkPolyData, ReadsUInt32HeadersOfEarlierFiles) {
  const std::vector<float> points = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  std::string file =
      "<VTKFile type=\"PolyData\" version=\"1.0\" byte_order=\"LittleEndian\" "
      "header_type=\"UInt32\"><PolyData><FieldData>"
      "<DataArray type=\"Float64\" Name=\"TimeValue\" format=\"ascii\">0.5</DataArray>"
      "<DataArray type=\"Float64\" Name=\"step\" format=\"ascii\">5</DataArray>"
      "<DataArray type=\"Float64\" Name=\"energy_kinetic\" format=\"ascii\">1</DataArray>"
      "<DataArray type=\"Float64\" Name=\"energy_spring\" format=\"ascii\">2</DataArray>"
      "<DataArray type=\"Float64\" Name=\"energy_gravity\" format=\"ascii\">3</DataArray>"
      "</FieldData><Piece>"
      "<DataArray type=\"Float32\" Name=\"velocity\" format=\"appended\" offset=\"0\"/>"
      "<DataArray type=\"Float32\" Name=\"stretch\" format=\"appended\" offset=\"40\"/>"
      "<DataArray type=\"Float32\" Name=\"Points\" format=\"appended\" offset=\"56\"/>"
      "</Piece></PolyData><AppendedData encoding=\"raw\">_";
  const auto append = [&](const void* data, uint32_t bytes) {
    file.append(reinterpret_cast<const char*>(&bytes), 4);
    file.append(static_cast<const char*>(data), bytes);
  };
  const std::vector<float> stretch = {1, 1, 1};
  append(points.data(), 36);
  append(stretch.data(), 12);
  append(points.data(), 36);
  file += "</AppendedData></VTKFile>";
  const fs::path path = fs::path(testing::TempDir()) / "frame_formats_uint32.vtp";
  std::ofstream(path, std::ios::binary) << file;
  const Frame read = read_vtp(path);
  EXPECT_EQ(read.positions, points);
  EXPECT_EQ(read.velocities, points);
  EXPECT_EQ(read.stretch, stretch);
  EXPECT_EQ(read.step, 5u);
  fs::remove(path);
}

TEST(VtkCollection, ListsTheFramesWithTheirTimes) {
  const fs::path path = fs::path(testing::TempDir()) / "frame_formats_test.pvd";
  {
    std::ofstream out(path);
    write_pvd(out, {{0.0, "frame_000000.vtp"}, {1.0 / 60, "frame_000001.vtp"}});
  }
  const std::vector<CollectionEntry> entries = read_pvd(path);
  ASSERT_EQ(entries.size(), 2u);
  EXPECT_EQ(entries[1].file, "frame_000001.vtp");
  EXPECT_DOUBLE_EQ(entries[1].time, 1.0 / 60);
  fs::remove(path);
}

// Times are read by the host's number parser: "1,5" and "0x10" are errors naming the file,
// not 1 and 16 (what std::stod makes of them).
TEST(VtkCollection, ATimeThatIsNotANumberIsAnErrorNamingTheFile) {
  const fs::path path = fs::path(testing::TempDir()) / "frame_formats_bad_time.pvd";
  for (const char* time : {"1,5", "0x10", "inf", ""}) {
    {
      std::ofstream out(path);
      out << "<VTKFile type=\"Collection\"><Collection>\n"
          << "<DataSet timestep=\"" << time << "\" file=\"frame_000000.vtp\"/>\n"
          << "</Collection></VTKFile>\n";
    }
    try {
      read_pvd(path);
      ADD_FAILURE() << "timestep \"" << time << "\" was accepted";
    } catch (const std::runtime_error& error) {
      const std::string message = error.what();
      EXPECT_NE(message.find(path.string()), std::string::npos) << message;
      EXPECT_NE(message.find("is not a number: \"" + std::string(time) + "\""), std::string::npos)
          << message;
    }
  }
  fs::remove(path);
}

TEST(VtkCollection, ADataSetWithoutTimestepOrFileIsAnErrorNamingTheFile) {
  const fs::path path = fs::path(testing::TempDir()) / "frame_formats_bad_dataset.pvd";
  for (const char* element : {"<DataSet file=\"frame_000000.vtp\"/>", "<DataSet timestep=\"0\"/>",
                              "<DataSet mytimestep=\"0\" file=\"a\"/>"}) {
    {
      std::ofstream out(path);
      out << "<VTKFile type=\"Collection\"><Collection>\n"
          << element << "\n</Collection></VTKFile>\n";
    }
    try {
      read_pvd(path);
      ADD_FAILURE() << element << " was accepted";
    } catch (const std::runtime_error& error) {
      EXPECT_EQ(std::string(error.what()),
                path.string() + ": DataSet without timestep or file: " + element);
    }
  }
  fs::remove(path);
}

TEST(PointCache, HeaderFollowsThePc2Layout) {
  std::ostringstream out;
  write_pc2_header(out, 2500, 7);
  const std::string header = out.str();
  ASSERT_EQ(header.size(), pc2_header_bytes);
  EXPECT_EQ(header.substr(0, 12), std::string("POINTCACHE2\0", 12));
  int32_t points = 0, samples = 0;
  std::memcpy(&points, header.data() + 16, 4);
  std::memcpy(&samples, header.data() + 28, 4);
  EXPECT_EQ(points, 2500);
  EXPECT_EQ(samples, 7);
}

}  // namespace
}  // namespace clothlab::io
