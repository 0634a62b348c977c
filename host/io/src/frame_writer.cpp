#include <algorithm>
#include <array>
#include <chrono>
#include <clothlab/host/errors.hpp>
#include <clothlab/io/atomic_file.hpp>
#include <clothlab/io/frame_formats.hpp>
#include <clothlab/io/frame_writer.hpp>
#include <condition_variable>
#include <cstdio>
#include <ctime>
#include <exception>
#include <fstream>
#include <mutex>
#include <string_view>
#include <thread>

namespace fs = std::filesystem;

namespace clothlab::io {

namespace {

// The state as the stepping thread copied it: raw bytes, decoded on the writer thread.
struct Snapshot {
  uint64_t step = 0;
  double time = 0;
  Cloth::RawState state;
  std::vector<Collider> colliders;  // at their poses then
};

// Frames the stepping thread may be ahead of the writer before it waits: enough to ride out
// a slow write (a disk flush) without holding more than a few frames' state.
constexpr std::size_t ring_slots = 4;

std::string frame_name(uint64_t index, const char* extension) {
  char name[64];
  std::snprintf(name, sizeof name, "frame_%06llu.%s", static_cast<unsigned long long>(index),
                extension);
  return name;
}

bool has(const std::vector<std::string>& formats, const char* format) {
  return std::find(formats.begin(), formats.end(), format) != formats.end();
}

constexpr const char* pc2_staging_name = ".frames.pc2.partial";

// Frames many times a second: atomic renames without fsync (a run that stops, however it
// stops, leaves whole files); run.json and the point cache, written once or twice, are synced.
constexpr Durability frame_durability = Durability::Renamed;
// Temporaries of an earlier, killed run are removed once when the writer starts: a sweep per
// frame would scan a folder that grows by a file or two every frame.
constexpr StaleTemporaries frame_sweep = StaleTemporaries::Skip;

double thread_cpu_s() {
  timespec now{};
  ::clock_gettime(CLOCK_THREAD_CPUTIME_ID, &now);
  return static_cast<double>(now.tv_sec) + 1e-9 * static_cast<double>(now.tv_nsec);
}

// frame_NNNNNN.vtp or .obj (six digits or more), frames.pvd, frames.pc2 or the staging file.
bool is_frame_file(std::string_view name) {
  if (name == "frames.pvd" || name == "frames.pc2" || name == pc2_staging_name) return true;
  constexpr std::string_view prefix = "frame_";
  if (!name.starts_with(prefix) || !(name.ends_with(".vtp") || name.ends_with(".obj")))
    return false;
  const std::string_view digits = name.substr(prefix.size(), name.size() - prefix.size() - 4);
  return digits.size() >= 6 &&
         std::all_of(digits.begin(), digits.end(), [](char c) { return c >= '0' && c <= '9'; });
}

// The files an earlier run left in the folder, so the folder shows one run.
void remove_earlier_frames(const fs::path& dir) {
  std::error_code error;
  for (const fs::directory_entry& entry : fs::directory_iterator(dir, error))
    if (entry.is_regular_file() && is_frame_file(entry.path().filename().string()))
      fs::remove(entry.path(), error);
}

}  // namespace

struct FrameWriter::Impl {
  FrameWriterOptions options;
  FrameMesh mesh;
  VtpTopology topology;
  // A one-thread copy of the cloth: the energy of a frame from the same code as the run's.
  Cloth energy_cloth;
  bool vtp = false, obj = false, pc2 = false;

  // Snapshot k lives in ring[k % ring_slots]; the stepping thread fills slot `submitted`
  // while fewer than ring_slots are unwritten, the writer empties slot `consumed`.
  std::array<Snapshot, ring_slots> ring;
  uint64_t submitted = 0, consumed = 0;
  bool closing = false;
  std::exception_ptr failure;
  mutable std::mutex mutex;
  std::condition_variable changed;

  bool finished = false;  // finish() ran

  // Writer thread only.
  uint64_t frames = 0;
  std::vector<CollectionEntry> index;
  std::ofstream pc2_staging;
  double writing_s = 0;      // wall time spent writing frames, for run.json
  double writing_cpu_s = 0;  // the writer thread's CPU time for them: what it takes from the
                             // stepping threads when every core steps
  Frame frame;
  VtpFile vtp_file;
  std::thread thread;

  Impl(const Scene& scene, const std::shared_ptr<const ClothModel>& model, Precision precision,
       FrameWriterOptions options_in)
      : options(std::move(options_in)),
        mesh(*model),
        topology(vtp_topology(mesh)),
        energy_cloth(scene, model, precision, PipelineOptions{true, 1}),
        vtp(has(options.formats, "vtp")),
        obj(has(options.formats, "obj")),
        pc2(has(options.formats, "pc2")) {}

  void write_run_json(const nlohmann::json& json) {
    io::write_file_atomically(options.dir / "run.json",
                              [&](std::ostream& out) { out << json.dump(2) << "\n"; });
  }

  void write(const Snapshot& snapshot) {
    frame.index = frames;
    frame.step = snapshot.step;
    frame.time = snapshot.time;
    energy_cloth.set_raw_state(snapshot.state);
    energy_cloth.positions(frame.positions);
    energy_cloth.velocities(frame.velocities);
    compute_stretch(mesh, frame.positions, frame.stretch);
    const Cloth::Energy energy = energy_cloth.energy();
    frame.energy = {energy.kinetic, energy.spring, energy.gravity};
    frame.colliders = snapshot.colliders;
    if (vtp) {
      const std::string name = frame_name(frames, "vtp");
      compose_vtp(vtp_file, topology, frame);
      io::write_file_atomically(options.dir / name, vtp_file.pieces, frame_durability, frame_sweep);
      index.push_back({frame.time, name});
      io::write_file_atomically(
          options.dir / "frames.pvd", [&](std::ostream& out) { write_pvd(out, index); },
          frame_durability, frame_sweep);
    }
    if (obj)
      io::write_file_atomically(
          options.dir / frame_name(frames, "obj"),
          [&](std::ostream& out) { write_obj(out, mesh, frame); }, frame_durability, frame_sweep);
    if (pc2) {
      pc2_staging.write(reinterpret_cast<const char*>(frame.positions.data()),
                        static_cast<std::streamsize>(frame.positions.size() * sizeof(float)));
      if (!pc2_staging)
        throw host::InputError("cannot write " + (options.dir / pc2_staging_name).string());
    }
    ++frames;
  }

  void write_loop() {
    for (;;) {
      uint64_t slot = 0;
      bool failed = false;
      {
        std::unique_lock lock(mutex);
        changed.wait(lock, [&] { return consumed < submitted || closing; });
        if (consumed == submitted) return;
        slot = consumed % ring_slots;
        failed = failure != nullptr;
      }
      if (!failed) {
        try {
          const auto start = std::chrono::steady_clock::now();
          const double cpu_start = thread_cpu_s();
          write(ring[slot]);
          writing_s +=
              std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
          writing_cpu_s += thread_cpu_s() - cpu_start;
        } catch (...) {
          std::lock_guard lock(mutex);
          failure = std::current_exception();
        }
      }
      {
        std::lock_guard lock(mutex);
        ++consumed;
      }
      changed.notify_all();
    }
  }

  void stop_thread() {
    {
      std::lock_guard lock(mutex);
      closing = true;
    }
    changed.notify_all();
    if (thread.joinable()) thread.join();
  }

  void rethrow_failure() {
    std::lock_guard lock(mutex);
    if (failure) std::rethrow_exception(failure);
  }

  // The staged positions behind a header that counts exactly the frames written.
  void write_point_cache() {
    pc2_staging.close();
    const fs::path staging = options.dir / pc2_staging_name;
    io::write_file_atomically(options.dir / "frames.pc2", [&](std::ostream& out) {
      write_pc2_header(out, mesh.vertex_count, frames);
      std::ifstream in(staging, std::ios::binary);
      out << in.rdbuf();
    });
    fs::remove(staging);
  }
};

FrameWriter::FrameWriter(const Scene& scene, const std::shared_ptr<const ClothModel>& model,
                         Precision precision, FrameWriterOptions options) {
  std::error_code error;
  fs::create_directories(options.dir, error);
  if (error || !fs::is_directory(options.dir))
    throw host::InputError("frames folder " + options.dir.string() + ": cannot create it: " +
                           (error ? error.message() : std::string("not a folder")));
  impl_ = std::make_unique<Impl>(scene, model, precision, std::move(options));
  Impl& impl = *impl_;
  remove_earlier_frames(impl.options.dir);
  io::remove_stale_temporaries_in(impl.options.dir);
  nlohmann::json run = impl.options.run;
  run["status"] = "running";
  run["frames"] = {{"every_steps", impl.options.every_steps}, {"formats", impl.options.formats}};
  try {
    impl.write_run_json(run);
  } catch (const io::WriteError& error) {
    // Before any step: an unwritable folder is bad input, not a failed run.
    throw host::InputError("frames folder " + impl.options.dir.string() + ": " + error.what());
  }
  if (impl.pc2) {
    impl.pc2_staging.open(impl.options.dir / pc2_staging_name, std::ios::binary | std::ios::trunc);
    if (!impl.pc2_staging)
      throw host::InputError("cannot write " + (impl.options.dir / pc2_staging_name).string());
  }
  // Sized now, so a submit copies into memory it already has.
  for (Snapshot& slot : impl.ring) impl.energy_cloth.copy_raw_state(slot.state);
  impl.thread = std::thread([&impl] { impl.write_loop(); });
}

FrameWriter::~FrameWriter() {
  if (!impl_) return;
  impl_->stop_thread();
  // A run ended by an exception never reached finish(): its point cache is still completed,
  // so every format holds the frames written so far.
  if (impl_->pc2 && !impl_->finished) {
    try {
      impl_->write_point_cache();
    } catch (...) {  // nothing to report to from a destructor; the .vtp sequence stands
    }
  }
}

bool FrameWriter::is_frame_step(uint64_t step) const {
  return step % impl_->options.every_steps == 0 || step == impl_->options.last_step;
}

void FrameWriter::submit(const Cloth& cloth, uint64_t step, double t) {
  Impl& impl = *impl_;
  uint64_t slot = 0;
  {
    std::unique_lock lock(impl.mutex);
    impl.changed.wait(lock,
                      [&] { return impl.submitted - impl.consumed < ring_slots || impl.failure; });
    if (impl.failure) std::rethrow_exception(impl.failure);
    slot = impl.submitted % ring_slots;
  }
  // The slot is the stepping thread's until submitted moves past it: no lock for the copy.
  Snapshot& snapshot = impl.ring[slot];
  snapshot.step = step;
  snapshot.time = t;
  cloth.copy_raw_state(snapshot.state);
  const std::span<const Collider> colliders = cloth.colliders();
  snapshot.colliders.assign(colliders.begin(), colliders.end());
  {
    std::lock_guard lock(impl.mutex);
    ++impl.submitted;
  }
  impl.changed.notify_all();
}

void FrameWriter::finish(const nlohmann::json& summary) {
  Impl& impl = *impl_;
  impl.stop_thread();
  impl.rethrow_failure();
  impl.finished = true;
  if (impl.pc2) impl.write_point_cache();
  nlohmann::json run = impl.options.run;
  run["status"] = "finished";
  run["frames"] = {
      {"every_steps", impl.options.every_steps},
      {"formats", impl.options.formats},
      {"written", impl.frames},
      {"writer_s_per_frame", impl.frames ? impl.writing_s / impl.frames : 0.0},
      {"writer_cpu_s_per_frame", impl.frames ? impl.writing_cpu_s / impl.frames : 0.0}};
  run["summary"] = summary;
  impl.write_run_json(run);
}

uint64_t FrameWriter::frames_written() const {
  std::lock_guard lock(impl_->mutex);
  return impl_->frames;
}

}  // namespace clothlab::io
