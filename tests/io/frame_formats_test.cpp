#include <gtest/gtest.h>

#include <clothlab/io/frame_formats.hpp>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "../../host/io/src/base64.hpp"

namespace clothlab::io {
namespace {

namespace fs = std::filesystem;

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

TEST(GridMesh, TwoCounterClockwiseTrianglesPerCell) {
  const GridMesh mesh{3, 4};
  const std::vector<int32_t> triangles = mesh.triangles();
  ASSERT_EQ(triangles.size(), 3 * mesh.triangle_count());
  EXPECT_EQ(mesh.triangle_count(), 12u);
  // Layout: column c at x = c, row r at y = -r; normals must point to +z.
  for (size_t t = 0; t < triangles.size(); t += 3) {
    const auto xy = [&](int32_t i) { return std::pair<double, double>(i % 4, -(i / 4)); };
    const auto [ax, ay] = xy(triangles[t]);
    const auto [bx, by] = xy(triangles[t + 1]);
    const auto [cx, cy] = xy(triangles[t + 2]);
    EXPECT_GT((bx - ax) * (cy - ay) - (by - ay) * (cx - ax), 0) << "triangle " << t / 3;
  }
}

TEST(GridMesh, StretchIsTheLongestAdjacentStructuralSpring) {
  const GridMesh mesh{2, 3};
  // Rest spacing 1 in both directions; the right column is pulled to x = 4 (spring 2x rest).
  std::vector<float> positions = {0, 0, 0, 1, 0, 0, 3, 0, 0, 0, -1, 0, 1, -1, 0, 3, -1, 0};
  std::vector<float> stretch;
  compute_stretch(mesh, 1.0, 1.0, positions, stretch);
  EXPECT_EQ(stretch, (std::vector<float>{1, 2, 2, 1, 2, 2}));
}

TEST(VtkPolyData, ReadsBackWhatItWrote) {
  const GridMesh mesh{2, 2};
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
  uint64_t triangles = 0;
  const Frame read = read_vtp(path, &triangles);
  EXPECT_EQ(read.positions, frame.positions);
  EXPECT_EQ(read.velocities, frame.velocities);
  EXPECT_EQ(read.stretch, frame.stretch);
  EXPECT_EQ(read.step, 120u);
  EXPECT_DOUBLE_EQ(read.time, 0.12);
  EXPECT_DOUBLE_EQ(read.energy.kinetic, 1.25);
  EXPECT_DOUBLE_EQ(read.energy.gravity, -2);
  EXPECT_EQ(triangles, 2u);
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
