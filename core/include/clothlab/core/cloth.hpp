// The core's C++ API, used by the host (never by plugins, which see only plugin.h/sdk.hpp).
//
// A Cloth owns the SoA state of one scene in one precision and the force pipeline built
// for it: only the stages the scene and the integrator need. It hands integrators a
// clothlab_system whose callbacks evaluate accelerations and vector updates.
#pragma once

#include <clothlab/ext/air.h>
#include <clothlab/plugin.h>

#include <array>
#include <clothlab/core/collider.hpp>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

namespace clothlab {

enum class Precision { Float32, Float64 };
const char* to_string(Precision precision);

struct SpringFamily {
  double ks = 0.0;
  double kd = 0.0;
};

// The drag and lift model of clothlab.air/1 (clothlab/ext/air.h); density 0 = no air.
struct Air {
  Vec3 wind_velocity{0, 0, 0};  // m/s
  double density = 0.0;         // kg/m^3
  double drag_coefficient = 0.0;
  double lift_coefficient = 0.0;
};

// An owned, validated copy of a scenario's clothlab_scene.
struct Scene {
  uint32_t rows = 1;
  uint32_t cols = 1;
  double width = 1.0;
  double height = 1.0;
  Vec3 origin{0, 0, 0};
  Vec3 col_axis{1, 0, 0};
  Vec3 row_axis{0, -1, 0};
  double total_mass = 1.0;
  SpringFamily structural, shear, flexion;
  Vec3 gravity{0, -9.81, 0};
  Vec3 wind_direction{1, 0, 0};
  double wind_strength = 0.0;
  Air air;  // from the scenario's clothlab.air/1, when it offers one
  std::vector<uint32_t> pinned;

  bool has_wind() const { return wind_strength != 0.0; }
  bool has_air() const {
    return air.density > 0.0 && (air.drag_coefficient > 0.0 || air.lift_coefficient > 0.0);
  }
  // Rest distance between neighbouring columns (rows) of the initial layout; 0 where there is
  // only one.
  double column_spacing() const { return cols > 1 ? width / (cols - 1) : 0.0; }
  double row_spacing() const { return rows > 1 ? height / (rows - 1) : 0.0; }
};

// Copies and validates; throws std::invalid_argument naming the bad field and value.
Scene scene_from_abi(const clothlab_scene& scene);
// The same for a scenario's air; throws std::invalid_argument naming "air.FIELD", the value and
// the allowed range.
Air air_from_abi(const clothlab_air& air);

struct SpringCounts {
  uint64_t structural = 0;
  uint64_t shear = 0;
  uint64_t flexion = 0;
  uint64_t total() const { return structural + shear + flexion; }
};
SpringCounts count_springs(uint32_t rows, uint32_t cols);

// The cloth's surface, 3 particle indices per triangle: each grid cell with corners
// a = (r, c), b = (r, c + 1), c' = (r + 1, c), d = (r + 1, c + 1) is the triangles (a, b, c')
// and (b, d, c'), the ones wind acts on, counter-clockwise about their normal
// col_axis x row_axis. Cells go column of cells by column of cells, top to bottom, so that
// each column of cells is one triangle strip.
std::vector<uint32_t> grid_triangles(uint32_t rows, uint32_t cols);

// Clouds of fewer particles run on the calling thread whatever PipelineOptions::threads says
// (a thread team costs more than it saves there). Checks of threaded behaviour use more.
inline constexpr std::size_t parallel_from_particles = 4096;

struct PipelineOptions {
  bool velocity_forces = true;  // false: no damping stage (integrator ignores v)
  int threads = 0;              // 0: all hardware threads
  // Steps bracketed by Cloth::begin_step / end_step run on the calling thread alone while a
  // step alone is faster than the team's, as when another process took a core (team_governor.hpp).
  bool adaptive_threads = true;
  // Runs a grid on the spring-list path meshes take instead of its row pipeline (as Box2D's
  // B2_FORCE_OVERFLOW): what tests hold the two paths equal with. The grid, jacobian,
  // definite-jacobian and cg-step extensions are then not offered.
  bool force_general_path = false;
};

// Cumulative counters since construction (or reset_counters), for the run summary.
struct StageCounters {
  uint64_t force_evals = 0;
  uint64_t springs_evaluated = 0;     // Hooke terms computed
  uint64_t springs_damped = 0;        // damping terms computed
  uint64_t normals_computed = 0;      // triangle normals for wind and air
  uint64_t particles_integrated = 0;  // active particle updates by vector helpers
  uint64_t steps_on_one_thread = 0;   // steps the adaptive team ran on the calling thread
  double internal_forces_s = 0.0;     // wall time in spring forces
  double external_forces_s = 0.0;     // wall time in gravity + wind + air
};

// Where the attached particles' targets come from (a scenario's clothlab.attachments/1, through
// the host): called inside steps, so it must not allocate.
class AttachmentSource {
 public:
  virtual ~AttachmentSource() = default;
  // Writes the targets at time t, 3 values per attached particle, particle-major; false when
  // one is not finite.
  virtual bool targets(double t, std::span<double> positions,
                       std::span<double> velocities) noexcept = 0;
};

struct ClothModel;

class Cloth {
 public:
  // The scene's rows x cols grid (build_grid_model).
  Cloth(const Scene& scene, Precision precision, PipelineOptions options);
  // Any cloth: `model` (cloth_model.hpp) gives the particles, springs and triangles; `scene` the
  // gravity, wind and air (its rows, cols and layout are not read).
  Cloth(const Scene& scene, std::shared_ptr<const ClothModel> model, Precision precision,
        PipelineOptions options);
  ~Cloth();
  Cloth(const Cloth&) = delete;
  Cloth& operator=(const Cloth&) = delete;

  // The table handed to integrator plugins; valid for the Cloth's lifetime.
  const clothlab_system& system() const;

  const Scene& scene() const;
  // The cloth as data: shared, immutable.
  const std::shared_ptr<const ClothModel>& model() const;
  Precision precision() const;
  uint32_t particle_count() const;
  const SpringCounts& springs() const;
  int threads() const;
  // Around each integrator step: lets the engine pick the team or the calling thread for the
  // step and the work up to the next begin_step (PipelineOptions::adaptive_threads). A host
  // that never calls them keeps every step on the team.
  void begin_step();
  void end_step();

  const StageCounters& counters() const;
  void reset_counters();

  // State as doubles, particle-major: out[3 * i + k].
  void positions(std::vector<double>& out) const;
  void velocities(std::vector<double>& out) const;
  // The same rounded to float32 in one pass (frame files: float32 whatever the precision).
  void positions(std::vector<float>& out) const;
  void velocities(std::vector<float>& out) const;
  void set_state(const std::vector<double>& x, const std::vector<double>& v);
  // The state as the cloth stores it (structure of arrays, its precision, padding included):
  // copying it out is two memcpy's, cheap enough for the step loop, and only a Cloth of the
  // same scene and precision can read it back (FrameWriter decodes frames on its own thread).
  struct RawState {
    std::vector<std::byte> x, v;
  };
  void copy_raw_state(RawState& out) const;
  // Throws std::invalid_argument if the state has another size than this cloth's.
  void set_raw_state(const RawState& state);
  bool state_is_finite() const;

  // Energy of the current state (J): kinetic, spring potential, gravitational potential
  // relative to the initial layout.
  struct Energy {
    double kinetic = 0, spring = 0, gravity = 0;
    double total() const { return kinetic + spring + gravity; }
  };
  Energy energy() const;
  // Current length over rest length: the largest and the mean, over all springs or over the
  // structural ones alone (the warp and weft threads: whether the cloth hangs like cloth or
  // like rubber; shear springs lengthen when the weave shears, which real cloth does easily).
  // A cloth without such springs counts as unstretched.
  // max_away_from_pins: the largest over the springs with neither end within two rows and two
  // columns of a pinned particle. A pin is a point load: the springs at it stretch more the
  // finer the mesh (a stress concentration, not the cloth). 1 when every spring is that near.
  struct Stretch {
    double max = 1, mean = 1;
    double max_away_from_pins = 1;
  };
  enum class Springs { All, Structural };
  Stretch stretch(Springs springs = Springs::All) const;
  // The nearest-rank percentile of length / rest length over the springs: the smallest ratio
  // that at least `fraction` (in (0, 1]) of them do not exceed; 1 without springs. A selection
  // over a copy of the ratios: for checks and reports, not the step loop.
  double stretch_percentile(Springs springs, double fraction) const;
  // The spring with the largest length / rest length: from particle `first` to `second`, on a
  // grid from (row, col) to (row + row_step, col + col_step) (all 0 on a mesh). Where the
  // maximum of stretch() sits (a corner, a fold, a free edge); one scalar pass, for reports
  // rather than the step loop.
  struct LongestSpring {
    double ratio = 1;
    uint32_t first = 0, second = 0;
    uint32_t row = 0, col = 0;
    uint32_t row_step = 0;
    int32_t col_step = 0;
  };
  LongestSpring longest_spring(Springs springs = Springs::All) const;
  double max_stretch() const { return stretch().max; }

  // The colliders at time t (the step's start), with their motion over the step, which
  // clothlab.contacts/1 keeps the cloth out of: a resolution at time t' meets each collider
  // moved at its velocity to t' (Collider::advanced). The host sets them before each step, which
  // is after the last (none: contacts are a no-op); each particle's path over the last step is
  // then judged against them (Contacts::particles_crossed). Allocates only when there are more
  // than ever before.
  void set_colliders(std::span<const Collider> colliders, double t);
  // The colliders where the last resolution met them (the step's start before any; the frames
  // draw them); valid until the next set_colliders.
  std::span<const Collider> colliders() const;
  // The cloth against the colliders where the last resolution, or set_colliders, put them: the
  // deepest penetration of a collider's surface (m), the largest depth past the thickness of the
  // collider it lies in (m) and how many particles lie inside one; and how many crossed one over
  // the step that the last set_colliders ended: their path from the step's start to its end,
  // relative to the collider between its poses at the two set_colliders calls, passed through
  // it or past its middle (tunnelled).
  struct Contacts {
    double max_penetration = 0;
    double max_depth_past_thickness = 0;
    uint32_t particles_inside = 0;
    uint32_t particles_crossed = 0;
  };
  Contacts contacts() const;
  // The energy clothlab.contacts/1 has added to the cloth since construction (J): over each
  // particle it moved, its kinetic and gravitational energy and its springs' energy after the
  // move less before, where that is positive (a moving collider pushing the cloth; a move that
  // took energy away, such as removing the velocity into a body, counts 0: a bound, not a
  // balance).
  double contact_work() const;

  // The particles clothlab.attachment-targets/1 moves to the targets `source` gives (each
  // pinned in the scene; `source` outlives the cloth). None (the default): the extension's
  // count is 0 and its move a no-op. Allocates. Throws std::invalid_argument for a particle
  // out of range or not pinned.
  void set_attachments(std::span<const uint32_t> particles, AttachmentSource& source);
  // Moves the attached particles of the cloth's own state to their targets at t (the host does
  // so before the first step); false when a target is not finite.
  bool move_attachments(double t);
  // What the attachments' work is sampled from (analysis::StabilityMonitor): at every pinned
  // particle, attached or held still (ascending index), its position and the force its springs
  // pull it with (Hooke, and the damping when the integrator uses velocity forces). Without
  // attachments nothing is sampled: both come back empty. Allocates only when there are more
  // pins than `out` held before.
  struct PinLoads {
    std::vector<double> positions, spring_forces;  // 3 per pinned particle
  };
  void pin_loads(PinLoads& out) const;
  // The momentum and mass of the particles that are not pinned: where gravity is the only force
  // from outside, their change of momentum less gravity's impulse is what the pins gave them.
  // One pass over the particles; allocates nothing.
  struct Momentum {
    Vec3 momentum{0, 0, 0};  // kg m/s
    double mass = 0;         // kg
  };
  Momentum free_momentum() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace clothlab
