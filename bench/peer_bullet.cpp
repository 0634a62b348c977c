// ClothLab's xpbd against a peer, Bullet's btSoftBody (Debian libbullet-dev), on the same
// cloth: a config's material and scenario (default configs/bench-300.yaml: cotton, 60 Hz
// frames) at side x side particles, the sheet and the flag. Bullet's patch
// (btSoftBodyHelpers::CreatePatch) has ClothLab's layout, node r * cols + c at the same
// position, the same total mass spread evenly, the same pins (mass 0), gravity and, on the
// flag, the same wind pressure (ClothLab's per-triangle model, applied to Bullet's nodes before
// each of its substeps); its links are ClothLab's Provot springs (structural, both shear
// diagonals, flexion two apart), structural at full stiffness (kLST 1), shear and flexion at
// their stiffness relative to the structural one.
//
// Each engine's cost knob is swept on one thread, cheapest first (xpbd: substeps x iterations
// in one step per frame; Bullet: substeps x piterations), and the first setting whose p99
// warp/weft stretch, the largest over the run's frames, stays within the limit is the engine's
// cheapest. Both stretches come from one function of the positions (grid_stretch.hpp); ClothLab's
// is checked against the engine's own Cloth::stretch_percentile every frame.
//
//   build/bin/clothlab_peer_bullet [config] [--side N] [--scenario sheet|flag] [--duration S]
//       [--limit L] [--integrator xpbd|xpbd_tethers] [--bullet S I] [--cpu-time] [--full]
//
// Default: both scenarios at side 30 for 1 s (a short run), limit 1.05, stopping at each
// engine's first setting within the limit, and stopping each setting's run at the first frame
// over the limit; the tables are --side 100 and --side 300. --full runs every setting of both
// ladders for all the frames.
#include <BulletSoftBody/btSoftBody.h>
#include <BulletSoftBody/btSoftBodyHelpers.h>
#include <BulletSoftBody/btSoftBodyRigidBodyCollisionConfiguration.h>
#include <BulletSoftBody/btSoftRigidDynamicsWorld.h>
#include <btBulletDynamicsCommon.h>

#include <algorithm>
#include <chrono>
#include <clothlab/config/yaml_settings.hpp>
#include <clothlab/core/cloth.hpp>
#include <clothlab/sdk.hpp>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <functional>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "bench_setup.hpp"
#include "grid_stretch.hpp"
#include "material_scene.hpp"
#include "run_config.hpp"

namespace clothlab::bench {
namespace {

struct Setting {
  int substeps, iterations;
  int cost() const { return substeps * iterations; }
};

// Cheapest first by nominal cost (substeps x iterations), fewer substeps first at equal cost.
std::vector<Setting> ladder(const std::vector<int>& substeps, const std::vector<int>& iterations) {
  std::vector<Setting> settings;
  for (const int s : substeps)
    for (const int i : iterations) settings.push_back({s, i});
  std::stable_sort(settings.begin(), settings.end(), [](const Setting& a, const Setting& b) {
    return a.cost() != b.cost() ? a.cost() < b.cost() : a.substeps < b.substeps;
  });
  return settings;
}

struct Outcome {
  double p99 = 0.0;  // the largest over the frames; infinite where the run broke
  double ms_per_frame = 0.0;
  int frames = 0;  // run: fewer than asked where the run broke or passed the stop
};

using Positions = std::vector<double>;  // 3 per particle, particle r * cols + c

double p99_of(const Scene& scene, const Positions& xyz) {
  return warp_weft_stretch_percentile(xyz, scene.rows, scene.cols, scene.row_spacing(),
                                      scene.column_spacing(), 0.99);
}

bool finite(const Positions& xyz) {
  return std::all_of(xyz.begin(), xyz.end(), [](double value) { return std::isfinite(value); });
}

// Seconds on the calling thread's CPU clock: both engines step on that thread alone, and on a
// loaded machine its CPU time leaves out the time it waited for a core.
double thread_cpu_seconds() {
  timespec now{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &now);
  return static_cast<double>(now.tv_sec) + 1e-9 * static_cast<double>(now.tv_nsec);
}

// Runs up to `frames` frames of `step` (one frame each call), reading positions after each. A
// run stops at the first frame whose p99 passes `stop` (the figure is the largest over the
// frames, so the setting is then over the limit whatever the later frames do).
Outcome run_frames(const Scene& scene, int frames, double stop, bool cpu_time,
                   const std::function<void()>& step, const std::function<Positions()>& positions,
                   const std::function<void(const Positions&)>& check) {
  Outcome outcome;
  double seconds = 0.0;
  while (outcome.frames < frames && outcome.p99 <= stop) {
    const auto start = std::chrono::steady_clock::now();
    const double cpu_start = cpu_time ? thread_cpu_seconds() : 0.0;
    step();
    seconds +=
        cpu_time ? thread_cpu_seconds() - cpu_start
                 : std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    ++outcome.frames;
    const Positions xyz = positions();
    if (!finite(xyz)) {
      outcome.p99 = INFINITY;
      break;
    }
    check(xyz);
    outcome.p99 = std::max(outcome.p99, p99_of(scene, xyz));
  }
  outcome.ms_per_frame = 1e3 * seconds / outcome.frames;
  return outcome;
}

// ClothLab: integrator `id` (xpbd) on one thread, float32, one step of inner substeps per frame.
Outcome run_clothlab(const Scene& scene, const std::string& id, Setting setting, double frame,
                     int frames, double stop, bool cpu_time) {
  const Cloth cloth(scene, Precision::Float32, PipelineOptions{true, 1, false});
  BoundIntegrator integrator(id, cloth,
                             {{"inner_substeps", std::to_string(setting.substeps)},
                              {"iterations", std::to_string(setting.iterations)},
                              {"threads", "1"}});
  const sdk::System<float> system(cloth.system());
  double t = 0.0;
  return run_frames(
      scene, frames, stop, cpu_time,
      [&] {
        try {
          integrator.step(t, frame);
        } catch (const std::exception&) {  // xpbd reports a diverged sweep: a broken run
        }
        t += frame;
      },
      [&] {
        Positions xyz(3 * std::size_t{system.particle_count()});
        for (uint32_t i = 0; i < system.particle_count(); ++i)
          for (std::size_t k = 0; k < 3; ++k) xyz[3 * i + k] = system.x()[k * system.stride() + i];
        return xyz;
      },
      [&](const Positions& xyz) {
        // The shared measure must be the engine's own: else the comparison measures two things.
        const double own = cloth.stretch_percentile(Cloth::Springs::Structural, 0.99);
        // Relative: a broken run's ratios reach 1e12, where the two sums round apart.
        if (std::abs(own - p99_of(scene, xyz)) > 1e-9 * std::max(1.0, std::abs(own)))
          throw std::runtime_error("grid_stretch.hpp's p99 " + std::to_string(p99_of(scene, xyz)) +
                                   " differs from Cloth::stretch_percentile's " +
                                   std::to_string(own));
      });
}

btVector3 bullet(const Vec3& v) {
  return {static_cast<btScalar>(v[0]), static_cast<btScalar>(v[1]), static_cast<btScalar>(v[2])};
}

// The position of grid point (row fraction, column fraction) of the rest layout.
btVector3 layout_point(const Scene& scene, double down, double across) {
  Vec3 p = scene.origin;
  for (std::size_t k = 0; k < 3; ++k)
    p[k] += across * scene.width * scene.col_axis[k] + down * scene.height * scene.row_axis[k];
  return bullet(p);
}

// Bullet's cloth in its own world, stepped a frame at a time.
class BulletCloth {
 public:
  BulletCloth(const Scene& scene, Setting setting)
      : scene_(scene),
        setting_(setting),
        dispatcher_(&collision_),
        world_(&dispatcher_, &broadphase_, &solver_, &collision_),
        triangles_(grid_triangles(scene.rows, scene.cols)) {
    btSoftBodyWorldInfo& info = world_.getWorldInfo();
    info.m_gravity = bullet(scene.gravity);
    info.air_density = 0;  // the flag's wind is ClothLab's pressure model, applied below
    info.water_density = 0;
    info.m_sparsesdf.Initialize();
    world_.setGravity(info.m_gravity);
    const int rows = static_cast<int>(scene.rows), cols = static_cast<int>(scene.cols);
    body_ = btSoftBodyHelpers::CreatePatch(info, layout_point(scene, 0, 0),
                                           layout_point(scene, 0, 1), layout_point(scene, 1, 0),
                                           layout_point(scene, 1, 1), cols, rows, 0, false);
    btSoftBody::Material* structural = body_->m_materials[0];
    structural->m_kLST = 1;
    const auto relative = [&](const SpringFamily& family) {
      btSoftBody::Material* material = body_->appendMaterial();
      material->m_kLST =
          static_cast<btScalar>(std::clamp(family.ks / scene.structural.ks, 0.0, 1.0));
      return material;
    };
    btSoftBody::Material* shear = relative(scene.shear);
    btSoftBody::Material* flexion = relative(scene.flexion);
    const auto node = [&](int r, int c) { return r * cols + c; };
    for (int r = 0; r < rows; ++r)
      for (int c = 0; c < cols; ++c) {
        if (r + 1 < rows && c + 1 < cols) body_->appendLink(node(r, c), node(r + 1, c + 1), shear);
        if (r + 1 < rows && c > 0) body_->appendLink(node(r, c), node(r + 1, c - 1), shear);
        if (c + 2 < cols) body_->appendLink(node(r, c), node(r, c + 2), flexion);
        if (r + 2 < rows) body_->appendLink(node(r, c), node(r + 2, c), flexion);
      }
    body_->setTotalMass(static_cast<btScalar>(scene.total_mass), false);
    for (const uint32_t pin : scene.pinned) body_->setMass(static_cast<int>(pin), 0);
    body_->m_cfg.piterations = setting.iterations;
    body_->m_cfg.collisions = 0;  // nothing to collide with; no self-collision in ClothLab either
    world_.addSoftBody(body_);
    if (scene.has_wind()) world_.setInternalTickCallback(&BulletCloth::before_substep, this, true);
  }
  ~BulletCloth() {
    world_.removeSoftBody(body_);
    delete body_;
  }
  BulletCloth(const BulletCloth&) = delete;
  BulletCloth& operator=(const BulletCloth&) = delete;

  void step(double frame) {
    world_.stepSimulation(static_cast<btScalar>(frame), setting_.substeps,
                          static_cast<btScalar>(frame / setting_.substeps));
  }

  Positions positions() const {
    Positions xyz;
    xyz.reserve(3 * static_cast<std::size_t>(body_->m_nodes.size()));
    for (int i = 0; i < body_->m_nodes.size(); ++i)
      for (int k = 0; k < 3; ++k) xyz.push_back(body_->m_nodes[i].m_x[k]);
    return xyz;
  }

 private:
  // ClothLab's wind (wind_kernel.hpp): F = strength * area * (n . w) n on each triangle, a
  // third to each corner. Bullet clears node forces after each substep, so they are added
  // before every one.
  static void before_substep(btDynamicsWorld* world, btScalar) {
    static_cast<BulletCloth*>(world->getWorldUserInfo())->add_wind();
  }
  void add_wind() {
    const btVector3 w = bullet(scene_.wind_direction).normalized();
    const btScalar sixth = static_cast<btScalar>(scene_.wind_strength / 6.0);
    const btAlignedObjectArray<btSoftBody::Node>& nodes = body_->m_nodes;
    for (std::size_t t = 0; t + 2 < triangles_.size(); t += 3) {
      const btVector3& a = nodes[static_cast<int>(triangles_[t])].m_x;
      const btVector3 n = (nodes[static_cast<int>(triangles_[t + 1])].m_x - a)
                              .cross(nodes[static_cast<int>(triangles_[t + 2])].m_x - a);
      const btScalar length = n.length();
      if (length <= 0) continue;
      const btVector3 share = n * (sixth * n.dot(w) / length);
      for (int k = 0; k < 3; ++k) body_->addForce(share, static_cast<int>(triangles_[t + k]));
    }
  }

  const Scene& scene_;
  Setting setting_;
  btSoftBodyRigidBodyCollisionConfiguration collision_;
  btCollisionDispatcher dispatcher_;
  btDbvtBroadphase broadphase_;
  btSequentialImpulseConstraintSolver solver_;
  btSoftRigidDynamicsWorld world_;
  std::vector<uint32_t> triangles_;
  btSoftBody* body_ = nullptr;
};

Outcome run_bullet(const Scene& scene, Setting setting, double frame, int frames, double stop,
                   bool cpu_time, const Positions& clothlab_start) {
  BulletCloth cloth(scene, setting);
  const Positions start = cloth.positions();
  for (std::size_t i = 0; i < start.size(); ++i)
    if (std::abs(start[i] - clothlab_start[i]) > 1e-5)
      throw std::runtime_error("Bullet's patch is not ClothLab's layout at particle " +
                               std::to_string(i / 3));
  return run_frames(
      scene, frames, stop, cpu_time, [&] { cloth.step(frame); }, [&] { return cloth.positions(); },
      [](const Positions&) {});
}

std::string percent(double p99) {
  if (!std::isfinite(p99)) return "broke";
  char text[32];
  std::snprintf(text, sizeof text, "%.2f %%", 100.0 * (p99 - 1.0));
  return text;
}

int run(int argc, char** argv) {
  std::string config_path = "configs/bench-300.yaml";
  std::vector<std::string> scenarios;
  int side = 30;
  double duration = 1.0, limit = 1.05;
  std::string integrator = "xpbd";
  double bullet_substeps = 0, bullet_iterations = 0;  // one Bullet setting instead of its ladder
  bool full = false;
  bool cpu_time = false;  // the thread's CPU time per frame instead of the wall time
  for (int k = 1; k < argc; ++k) {
    const std::string arg = argv[k];
    const bool has_value = k + 1 < argc;
    if (arg == "--side" && has_value) {
      side = static_cast<int>(number_of(arg, argv[++k]));
    } else if (arg == "--scenario" && has_value) {
      scenarios.emplace_back(argv[++k]);
    } else if (arg == "--duration" && has_value) {
      duration = number_of(arg, argv[++k]);
    } else if (arg == "--limit" && has_value) {
      limit = number_of(arg, argv[++k]);
    } else if (arg == "--bullet" && k + 2 < argc) {
      bullet_substeps = number_of(arg, argv[++k]);
      bullet_iterations = number_of(arg, argv[++k]);
    } else if (arg == "--integrator" && has_value) {
      integrator = argv[++k];
    } else if (arg == "--cpu-time") {
      cpu_time = true;
    } else if (arg == "--full") {
      full = true;
    } else if (arg.rfind("--", 0) == 0) {
      std::fprintf(stderr, "clothlab_peer_bullet: unknown option '%s'\n", arg.c_str());
      return 2;
    } else {
      config_path = arg;
    }
  }
  if (side < 3 || side > 1000 || !(duration > 0.0 && duration <= 60.0) || !(limit > 1.0) ||
      bullet_substeps < 0 || bullet_substeps > 1000 || bullet_iterations < 0 ||
      bullet_iterations > 1000 || (bullet_substeps == 0) != (bullet_iterations == 0) ||
      std::floor(bullet_substeps) != bullet_substeps ||
      std::floor(bullet_iterations) != bullet_iterations) {
    std::fprintf(stderr,
                 "clothlab_peer_bullet: --side must be in [3, 1000], --duration in (0, 60] s, "
                 "--limit > 1, --bullet substeps and iterations whole numbers in [1, 1000]\n");
    return 2;
  }
  if (scenarios.empty()) scenarios = {"sheet", "flag"};
  cli::RunConfig config = cli::resolve_run_config(config::read_config_file(config_path));
  if (!config.material) {
    std::fprintf(stderr, "%s: no material.* (the benchmark is for a material's cloth)\n",
                 config_path.c_str());
    return 2;
  }
  const double rate = config.frame_rate > 0 ? config.frame_rate : 60.0;  // the host's default
  const double frame = 1.0 / rate;
  const int frames = std::max(1, static_cast<int>(std::lround(duration * rate)));
  const std::vector<Setting> xpbd_ladder = ladder({1, 2, 4, 8, 16, 32, 64, 96}, {1, 2, 4});
  // --bullet times one setting (at a large side each takes minutes): its row says whether it
  // is within the limit, not whether it is the cheapest.
  const std::vector<Setting> bullet_ladder =
      bullet_substeps > 0 ? std::vector<Setting>{{static_cast<int>(bullet_substeps),
                                                  static_cast<int>(bullet_iterations)}}
                          : ladder({1, 2, 4, 8, 16, 32, 64}, {1, 2, 4, 8, 16, 32, 64, 128});
  std::printf(
      "%s (%s), %dx%d, %d frames at %g Hz, one thread; p99 warp/weft stretch limit %.2f %%; "
      "ms per frame in %s\n",
      config_path.c_str(), config.material->name.c_str(), side, side, frames, rate,
      100.0 * (limit - 1.0), cpu_time ? "the thread's CPU time" : "wall time");
  for (const std::string& id : scenarios) {
    config.scenario = id;
    const Scene scene = make_material_scene(config, side);
    Positions start;
    {
      const Cloth cloth(scene, Precision::Float32, PipelineOptions{true, 1, false});
      const sdk::System<float> system(cloth.system());
      for (uint32_t i = 0; i < system.particle_count(); ++i)
        for (std::size_t k = 0; k < 3; ++k) start.push_back(system.x()[k * system.stride() + i]);
    }
    std::printf(
        "\n%s\n| engine | substeps | iterations | p99 stretch | ms per frame | frames |\n"
        "|---|---|---|---|---|---|\n",
        id.c_str());
    // A setting over the limit stops there, but with --full, which wants every figure.
    const double stop = full ? INFINITY : limit;
    const auto sweep = [&](const char* engine, const std::vector<Setting>& settings,
                           const std::function<Outcome(Setting)>& run_one) {
      for (const Setting& setting : settings) {
        const Outcome outcome = run_one(setting);
        const bool within = outcome.p99 <= limit;
        std::printf("| %s | %d | %d | %s | %.2f | %d |%s\n", engine, setting.substeps,
                    setting.iterations, percent(outcome.p99).c_str(), outcome.ms_per_frame,
                    outcome.frames, within ? " within" : "");
        std::fflush(stdout);
        if (within && !full) return;
      }
    };
    sweep(("clothlab " + integrator).c_str(), xpbd_ladder, [&](Setting s) {
      return run_clothlab(scene, integrator, s, frame, frames, stop, cpu_time);
    });
    sweep("bullet", bullet_ladder,
          [&](Setting s) { return run_bullet(scene, s, frame, frames, stop, cpu_time, start); });
  }
  return 0;
}

}  // namespace
}  // namespace clothlab::bench

int main(int argc, char** argv) {
  try {
    return clothlab::bench::run(argc, argv);
  } catch (const std::exception& error) {
    std::fprintf(stderr, "clothlab_peer_bullet: %s\n", error.what());
    return 1;
  }
}
