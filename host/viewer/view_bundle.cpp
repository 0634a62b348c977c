#include "view_bundle.hpp"

#include <clothlab/host/errors.hpp>
#include <clothlab/io/atomic_file.hpp>
#include <clothlab/io/base64.hpp>
#include <clothlab/io/frame_formats.hpp>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <system_error>

namespace fs = std::filesystem;

namespace clothlab::viewer {

namespace {

constexpr const char* asset_files[] = {"index.html", "viewer.js", "framing.js", "viewer.css",
                                       "three.min.js"};

nlohmann::json read_run_json(const fs::path& dir) {
  std::ifstream stream(dir / "run.json");
  if (!stream)
    throw host::InputError(dir.string() +
                           ": no run.json beside the frames; allowed: a folder "
                           "written by clothlab --frames");
  try {
    return nlohmann::json::parse(stream);
  } catch (const nlohmann::json::exception& error) {
    throw host::InputError((dir / "run.json").string() + ": not JSON: " + error.what());
  }
}

template <class T>
std::string base64_of(const std::vector<T>& values) {
  std::string text;
  io::append_base64(text, values.data(), values.size() * sizeof(T));
  return text;
}

// One run as a statement of runs.js; frames are read one at a time.
void write_run(std::ostream& out, const fs::path& dir, size_t max_frames) {
  const fs::path index_path = dir / "frames.pvd";
  if (!fs::is_regular_file(index_path))
    throw host::InputError(dir.string() +
                           ": no frames here (no frames.pvd); write them with "
                           "clothlab --frames " +
                           dir.string());
  std::vector<io::CollectionEntry> entries;
  try {
    entries = io::read_pvd(index_path);
  } catch (const std::exception& error) {
    throw host::InputError(error.what());
  }
  if (entries.empty()) throw host::InputError(index_path.string() + ": lists no frames");
  const nlohmann::json run = read_run_json(dir);
  // run.json's vertex count; folders written before it had one are grids of rows x cols.
  const uint64_t vertices =
      run.value("vertices", run.value("rows", uint64_t{0}) * run.value("cols", uint64_t{0}));
  const size_t stride = (entries.size() + max_frames - 1) / max_frames;

  nlohmann::json times = nlohmann::json::array(), energy = nlohmann::json::array();
  // The first frame's collider shapes, every frame's poses (a pose: position x y z, then the
  // orientation quaternion w x y z).
  nlohmann::json colliders = nlohmann::json::array(), collider_poses = nlohmann::json::array();
  std::string positions = "[", stretch = "[";
  std::vector<uint32_t> triangles;  // the first frame's: every frame has the same
  for (size_t i = 0; i < entries.size(); i += stride) {
    io::Frame frame;
    try {
      frame = io::read_vtp(dir / entries[i].file, i == 0 ? &triangles : nullptr);
    } catch (const std::exception& error) {
      throw host::InputError(error.what());
    }
    if (frame.positions.size() != 3 * vertices)
      throw host::InputError((dir / entries[i].file).string() + ": " +
                             std::to_string(frame.positions.size() / 3) +
                             " points, run.json's mesh " + std::to_string(vertices));
    if (i == 0) {
      for (const Collider& collider : frame.colliders)
        colliders.push_back({{"shape", std::string(to_string(collider.shape))},
                             {"radius", collider.radius},
                             {"end_radius", collider.end_radius},
                             {"half_length", collider.half_length},
                             {"half_extents", collider.half_extents}});
    }
    if (frame.colliders.size() != colliders.size())
      throw host::InputError((dir / entries[i].file).string() + ": " +
                             std::to_string(frame.colliders.size()) +
                             " colliders, the first frame " + std::to_string(colliders.size()));
    nlohmann::json poses = nlohmann::json::array();
    for (const Collider& collider : frame.colliders) {
      for (double value : collider.pose.position) poses.push_back(value);
      for (double value : collider.pose.orientation) poses.push_back(value);
    }
    collider_poses.push_back(std::move(poses));
    times.push_back(entries[i].time);
    energy.push_back({frame.energy.kinetic, frame.energy.spring, frame.energy.gravity});
    for (auto [text, values] :
         {std::pair{&positions, &frame.positions}, std::pair{&stretch, &frame.stretch}}) {
      text->append(i ? ",\"" : "\"");
      text->append(base64_of(*values));
      text->push_back('"');
    }
  }
  const nlohmann::json head = {{"name", dir.string()},
                               {"run", run},
                               {"rows", run.value("rows", 0)},
                               {"cols", run.value("cols", 0)},
                               {"vertices", vertices},
                               {"triangles", base64_of(triangles)},
                               {"times", times},
                               {"energy", energy},
                               {"colliders", colliders},
                               {"collider_poses", collider_poses}};
  const std::string head_text = head.dump();
  out << "CLOTHLAB_RUNS.push(Object.assign(" << head_text << ", {positions: " << positions
      << "], stretch: " << stretch << "]}));\n";
}

}  // namespace

fs::path assets_beside_executable() {
  std::error_code error;
  const fs::path executable = fs::read_symlink("/proc/self/exe", error);
  return executable.parent_path().parent_path() / "share" / "clothlab" / "viewer";
}

fs::path write_view_bundle(const ViewRequest& request) {
  for (const char* name : asset_files)
    if (!fs::is_regular_file(request.assets / name))
      throw host::InputError("viewer files missing: " + (request.assets / name).string() +
                             " (build the clothlab target, or install it)");
  std::error_code error;
  fs::create_directories(request.out, error);
  if (error || !fs::is_directory(request.out))
    throw host::InputError("--out " + request.out.string() + ": cannot create the folder: " +
                           (error ? error.message() : std::string("not a folder")));
  clothlab::io::write_file_atomically(request.out / "runs.js", [&](std::ostream& out) {
    out << "// Written by clothlab view.\nwindow.CLOTHLAB_RUNS = [];\n";
    for (const fs::path& run : request.runs) write_run(out, run, request.max_frames);
  });
  for (const char* name : asset_files)
    clothlab::io::write_file_atomically(request.out / name, [&](std::ostream& out) {
      std::ifstream in(request.assets / name, std::ios::binary);
      out << in.rdbuf();
    });
  return fs::absolute(request.out / "index.html");
}

}  // namespace clothlab::viewer
