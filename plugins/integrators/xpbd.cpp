// XPBD: the springs as compliant distance constraints (Macklin, Mueller, Chentanez 2016,
// "XPBD: position-based simulation of compliant constrained dynamics"), stepped with
// substeps of one iteration each by default (Macklin et al. 2019, "Small steps in physics
// simulation").
//
// Per substep of length h = dt / substeps:
//   predict    dx = h (v + h a_ext(x))                        (gravity, wind: the host's
//                                                             external-forces extension)
//   project    lambda = 0, then `iterations` Gauss-Seidel sweeps over the springs, colour
//              by colour (the topology extension's independent sets), each colour's springs
//              in parallel: no two share a particle, so every thread count gives the same bits
//   tethers    (option, xpbd_tethers.hpp) each free particle's long-range attachments to
//              pinned particles, |p_i - p_anchor| <= (1 + slack) rest, projected once
//   velocity   v = dx / h,  x += dx
// x stays at the substep's start while the projections move only dx, the substep's
// displacement; the springs see the positions x + dx as (x_i - x_j) + (dx_i - dx_j). So v
// never comes from x - x_prev: in float32 a substep's motion (g h^2 is ~1e-8 m at h = 25 us)
// is below the rounding of x itself and would be lost, and the cloth would not start to fall.
//
// One spring k joining i and j at positions p = x + dx, C = |p_i - p_j| - rest,
// n = (p_i - p_j) / |p_i - p_j|:
// compliance alpha = 1 / ks and Rayleigh damping beta = kd (the spring's damping force
// -kd (n . (v_i - v_j)) n is -beta grad C dC/dt), so with alpha~ = alpha / h^2,
// beta~ = h^2 beta and gamma = alpha~ beta~ / h = alpha beta / h the paper's eq. 26 reads
//   dlambda = (-C - alpha~ lambda - gamma n.(dx_i - dx_j)) / ((1 + gamma)(w_i + w_j) + alpha~)
// with dx the substep's displacement. Multiplied through by ks h^2 it needs no division by ks (a
// spring with ks = 0 is a pure damper) and its denominator is >= 1:
//   dlambda = (-ks h^2 C - lambda - kd h n.(dx_i - dx_j)) / ((ks h^2 + kd h)(w_i + w_j) + 1)
//   dx_i += w_i dlambda n,  dx_j -= w_j dlambda n.
// lambda accumulates over the iterations of a substep and is reset once per substep, never
// per iteration: resetting it per iteration would make the stiffness grow with the iteration
// count (the peer bug newton#2933).
//
// On the Provot grid (xpbd_grid.hpp) a substep runs as wavefronts over the rows instead
// of one pass over the cloth per colour: the phases (predict, each iteration's colours,
// velocity) visit row T - lag(phase) at wavefront time T, the lags growing by each
// colour's row reach (0, 1 or 2 rows), so every spring sees its ends exactly as the
// colour-by-colour order leaves them while the rows in flight stay in cache. With several
// threads the rows split into two bands at a boundary B: one team runs the wavefront down
// from row 0, the other up from the last row (there a phase visits start row
// rows - 1 - T + lag(phase) - its row reach), each touching only its own band's rows, so
// the two never wait for each other nor share a row in flight. B is where the two meet:
// the bands claim rows as they go (xpbd_bands.hpp). The rows next to B that
// neither wavefront reached (lag(phase) below B, lag(phase) - reach above it) are then
// projected phase by phase, each band's first thread on its side of B, the two meeting
// after each phase. Within a team each thread takes a contiguous run
// of phases and waits only for its predecessor to finish the same wavefront time. Every
// spring sees the same values in any split: the bits do not depend on the thread count.
// On the grid the substep's displacement dx lives in v's memory (the pins' velocities
// wait in the scratch array), and runs of springs whose ends all have the grid's common
// inverse mass skip the weights (xpbd_row_kernel.hpp).
//
// Tethers are a model change, not a solver setting: where the spring dynamics would strain the
// cloth along a tether by more than the slack, the tethered cloth converges (in h) to another
// solution, so they are off by default (`tethers` 0) and the accuracy below holds without them.
//
// Accuracy: one converged projection per substep is backward Euler on the elastic dynamics
// (same equation as its Newton step for a single spring), so XPBD converges at first order
// in h to the spring dynamics with the scene's ks and kd; one iteration per substep adds an
// O(h^2) per-step Gauss-Seidel error, which keeps the method first order.
#include <omp.h>

#include <algorithm>
#include <array>
#include <bit>
#include <clothlab/sdk.hpp>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <optional>
#include <type_traits>
#include <utility>
#include <vector>

#include "scratch_vectors.hpp"
#include "xpbd_bands.hpp"
#include "xpbd_grid.hpp"
#include "xpbd_row_kernel.hpp"
#include "xpbd_tethers.hpp"

namespace clothlab::builtin {
namespace {

// Smaller clothes run on the calling thread: a colour of fewer than ~5000 springs is not
// worth the barrier that ends it (12 barriers per sweep).
constexpr uint32_t parallel_from_springs = 65536;
// The general path projects tethers in blocks of particles, a vector loop each.
constexpr long tether_block = 256;

// One spring as the projection reads it, stored colour by colour.
template <class Real>
struct Constraint {
  uint32_t first, second;
  Real rest, ks, kd;
  Real first_weight, second_weight;  // inverse masses; 0 for a pinned end
};

// The constraints of one precision and their multipliers: one lambda per constraint, or on
// the grid n per colour (from the row's first particle on, see ColorRow), kept only when
// a substep runs more than one iteration.
template <class Real>
struct Constraints {
  std::vector<Constraint<Real>> springs;
  std::vector<Real> lambda;
};

// One stage of a substep on the grid, applied row by row.
struct Phase {
  enum class Kind : uint8_t { predict, project, tether, velocity };
  Kind kind;
  uint32_t color;          // project: the grid layout's colour
  uint32_t iteration;      // project
  uint32_t lag;            // wavefront times before its row 0, going down
  uint32_t upward_offset;  // lag - the phase's row reach: going up, the start row's offset
  uint64_t cost;           // work units, for splitting the phases between threads
};

// The teams of the grid sweep: two bands (xpbd_bands.hpp), the one going down run by
// threads [0, lower_threads), or one band of all threads.
struct Bands {
  bool two;
  int lower_threads;
};

// Columns [begin, end) of a grid row that hull its particles of another inverse mass than
// the grid's uniform one; begin >= end: none.
struct ColumnSpan {
  uint32_t begin, end;
};

}  // namespace

// Built twice from this file (plugins/integrators/CMakeLists.txt): `xpbd`, tethers off, and
// `xpbd_tethers`, the same code with tethers on by default, so that a search over the plugin
// path (clothlab --choose) weighs the tethered model beside the plain one.
#ifdef CLOTHLAB_XPBD_TETHERED
inline constexpr bool tethered_build = true;
#else
inline constexpr bool tethered_build = false;
#endif

struct Xpbd {
  static constexpr const char* id = tethered_build ? "xpbd_tethers" : "xpbd";
  static constexpr const char* name = tethered_build
                                          ? "XPBD with long-range attachments (tethers) to the pins"
                                          : "XPBD distance constraints with substeps";
  static constexpr const char* version = "1.1.0";
  static constexpr const char* description =
      tethered_build
          ? "xpbd with tethers 3 by default: Kim et al. 2012 long-range attachments, each free "
            "particle at most (1 + tether_slack) x its initial distance from its pins"
          : "Macklin et al. 2016/2019: springs as compliant constraints (alpha = 1/ks, damping "
            "eq. 26), Gauss-Seidel by spring colour, substeps; first order, unconditionally "
            "stable";
  static constexpr uint32_t order = 1;
  // No eval_acceleration calls: its cost is substeps x iterations passes over the springs.
  static constexpr uint32_t evals_per_step = 0;
  // The damping (kd) is part of the constraint projection; the flag makes the host and the
  // conformance runner treat the scene's damping as present.
  static constexpr uint32_t flags = CLOTHLAB_INTEGRATOR_USES_VELOCITY_FORCES;
  static constexpr std::array<clothlab_param_spec, 5> params{
      sdk::int_param("substeps", 40, 1, 1000, "substeps per step (h = dt / substeps)"),
      sdk::int_param("iterations", 1, 1, 100, "Gauss-Seidel sweeps over the springs per substep"),
      sdk::int_param("threads", 0, 0, 256,
                     "threads for the colour sweeps; 0 = all (omp_get_max_threads)"),
      sdk::int_param("tethers", tethered_build ? 3 : 0, 0, 16,
                     "long-range attachments per free particle to pinned particles (the nearest "
                     "pin of each pinned island, then pins spread along it); 0 = off"),
      sdk::real_param("tether_slack", 0.0, 0.0, 1.0, "",
                      "a tether's max length is (1 + tether_slack) x the particle's straight-line "
                      "distance to its pin at prepare"),
  };
  static constexpr clothlab_integrator_traits traits{
      sizeof(clothlab_integrator_traits),
      CLOTHLAB_TRAIT_UNCONDITIONALLY_STABLE | CLOTHLAB_TRAIT_ITERATIVE, "substeps", "iterations"};

  explicit Xpbd(const sdk::Params& values)
      : substeps_(static_cast<int>(values.integer("substeps"))),
        iterations_(static_cast<int>(values.integer("iterations"))),
        requested_threads_(static_cast<int>(values.integer("threads"))),
        tethers_per_particle_(static_cast<uint32_t>(values.integer("tethers"))),
        tether_slack_(values.real("tether_slack")) {}

  template <class Real>
  void prepare(sdk::System<Real>& system) {
    const sdk::Topology topology = system.topology();
    (void)system.external_forces();  // fails here, not in step, when the host lacks it
    scratch_.allocate(system);
    Constraints<Real>& constraints = constraints_for<Real>();
    tethers_for<Real>().build(topology, system.x(), system.stride(), system.inverse_mass(),
                              tethers_per_particle_, tether_slack_);
    grid_ = recognise_grid(topology);
    if (grid_) {
      constraints.springs.clear();
      constraints.lambda.assign(
          iterations_ > 1 ? grid_->colors.size() * system.particle_count() : 0, 0);
      build_phases(tethers_for<Real>().slots());
      find_uniform_weight(system.inverse_mass());
    } else {
      build_constraints(system, topology, constraints.springs);
      constraints.lambda.assign(constraints.springs.size(), 0);
    }
    const int threads = requested_threads_ == 0 ? omp_get_max_threads() : requested_threads_;
    threads_ = topology.spring_count() >= parallel_from_springs ? std::max(threads, 1) : 1;
    progress_ = std::make_unique<Progress[]>(static_cast<std::size_t>(threads_));
    // The first parallel region builds the thread team (allocates): here, not in step.
    if (threads_ > 1) {
#pragma omp parallel num_threads(threads_)
      { (void)omp_get_thread_num(); }
    }
  }

  template <class Real>
  void step(sdk::System<Real>& system, double t, double dt) {
    const auto [external_acceleration, displacement] = scratch_.bind(system);
    if (dt == 0.0) return;
    const sdk::ExternalForces<Real> external = system.external_forces();
    const bool wind = external.depends_on_position();
    const double h = dt / substeps_;
    if (!wind) external.acceleration(t, system.x(), external_acceleration);
    if (tethers_for<Real>().active())
      tethers_for<Real>().refresh_anchors(system.x(), system.stride());
    for (int substep = 0; substep < substeps_; ++substep) {
      if (wind) external.acceleration(t + substep * h, system.x(), external_acceleration);
      if (!advance_substep(system, h, external_acceleration, displacement))
        throw sdk::Error(CLOTHLAB_ERROR_NUMERICAL, "non-finite velocity in the substep at t = " +
                                                       std::to_string(t + substep * h));
    }
  }

 private:
  template <class Real>
  struct Substep {
    const Constraint<Real>* constraints;
    Real* lambda;
    const Real* inverse_mass;
    const Real* external_acceleration;
    // x's change in this substep, exact where x's rounding is not; the grid path keeps it
    // in v and this holds its pins' velocities
    Real* displacement;
    Real* x;
    Real* v;
    const Tethers<Real>* tethers;  // nullptr: off
    uint32_t particle_count;
    std::size_t stride;
    Real h, h_squared, inverse_h;
  };

  template <class Real>
  Constraints<Real>& constraints_for() {
    if constexpr (sizeof(Real) == 4)
      return constraints_f32_;
    else
      return constraints_f64_;
  }
  template <class Real>
  Tethers<Real>& tethers_for() {
    if constexpr (sizeof(Real) == 4)
      return tethers_f32_;
    else
      return tethers_f64_;
  }

  // Copies the springs colour by colour; springs with both ends pinned never move and are
  // left out (their colour ranges shrink accordingly).
  template <class Real>
  void build_constraints(const sdk::System<Real>& system, const sdk::Topology& topology,
                         std::vector<Constraint<Real>>& out) {
    const Real* inverse_mass = system.inverse_mass();
    out.clear();
    out.reserve(topology.spring_count());
    color_offsets_.assign(1, 0);
    for (uint32_t color = 0; color < topology.spring_color_count(); ++color) {
      for (uint32_t k : topology.spring_color(color)) {
        const uint32_t i = topology.first()[k], j = topology.second()[k];
        if (inverse_mass[i] == 0 && inverse_mass[j] == 0) continue;
        out.push_back({i, j, static_cast<Real>(topology.rest_length()[k]),
                       static_cast<Real>(topology.ks()[k]), static_cast<Real>(topology.kd()[k]),
                       inverse_mass[i], inverse_mass[j]});
      }
      color_offsets_.push_back(static_cast<uint32_t>(out.size()));
    }
  }

  // One substep; false when a velocity came out non-finite. The sweeps' worksharing loops
  // run on the team of a parallel region, or, on one thread, orphaned (no team, no barrier
  // cost, no allocation).
  template <class Real>
  bool advance_substep(sdk::System<Real>& system, double h, const Real* external_acceleration,
                       Real* displacement) {
    Constraints<Real>& constraints = constraints_for<Real>();
    const Substep<Real> substep{constraints.springs.data(),
                                constraints.lambda.empty() ? nullptr : constraints.lambda.data(),
                                system.inverse_mass(),
                                external_acceleration,
                                displacement,
                                system.x(),
                                system.v(),
                                tethers_for<Real>().active() ? &tethers_for<Real>() : nullptr,
                                system.particle_count(),
                                system.stride(),
                                static_cast<Real>(h),
                                static_cast<Real>(h * h),
                                static_cast<Real>(1.0 / h)};
    if (grid_) {
      if (threads_ == 1) return grid_sweep(substep, 0, 1);
      for (int thread = 0; thread < threads_; ++thread) progress_[thread].reset();
      for (int side = 0; side < 2; ++side) seam_progress_[side].reset();
      claims_->reset(grid_->rows, band_reserve());
      bool finite = true;
#pragma omp parallel num_threads(threads_) reduction(&& : finite)
      finite = grid_sweep(substep, omp_get_thread_num(), omp_get_num_threads());
      return finite;
    }
    if (threads_ == 1) return sweep(substep);
    bool finite = true;
#pragma omp parallel num_threads(threads_) reduction(&& : finite)
    finite = sweep(substep);
    return finite;
  }

  // The phases of a substep in Gauss-Seidel order and their lags: a phase may visit a row
  // once every earlier phase is done with all rows its springs reach (its row step below),
  // and a later phase reaches no row it has yet to visit.
  void build_phases(uint32_t tether_slots) {
    const GridLayout& grid = *grid_;
    phases_.clear();
    const uint64_t row_of_particles = grid.cols;
    phases_.push_back({Phase::Kind::predict, 0, 0, 0, 0, grid.rows * row_of_particles / 3});
    uint32_t lag = 0;
    for (uint32_t iteration = 0; iteration < static_cast<uint32_t>(iterations_); ++iteration)
      for (uint32_t c = 0; c < grid.colors.size(); ++c) {
        const GridColor& color = grid.colors[c];
        lag += color.step().row_step;
        uint64_t rows = 0;
        for (uint32_t r = 0; r < grid.rows; ++r) rows += color.starts_in_row(r);
        phases_.push_back({Phase::Kind::project, c, iteration, lag, lag - color.step().row_step,
                           rows * (color.col_end - color.col_begin)});
      }
    // Tethers move only their own particle: like the velocity phase, a row's may run as soon
    // as the last colour is done with it, going down or up.
    if (tether_slots > 0)
      phases_.push_back(
          {Phase::Kind::tether, 0, 0, lag, lag, grid.rows * row_of_particles * tether_slots / 4});
    phases_.push_back({Phase::Kind::velocity, 0, 0, lag, lag, grid.rows * row_of_particles / 3});
    // A thread publishes its progress every few rows' worth of ~2000 columns: each handoff
    // can cost a context switch on a loaded machine, one per narrow row would dominate.
    publish_every_ = std::max<uint32_t>(1, 2048 / grid.cols);
  }

  // The inverse mass of the grid's middle particle, taken as the uniform one (most cloths
  // are all one mass but a few pins), and each row's columns of another.
  template <class Real>
  void find_uniform_weight(const Real* inverse_mass) {
    const uint32_t rows = grid_->rows, cols = grid_->cols;
    const Real uniform = inverse_mass[std::size_t{rows / 2} * cols + cols / 2];
    uniform_weight_ = uniform;
    varied_columns_.assign(rows, ColumnSpan{cols, 0});
    for (uint32_t r = 0; r < rows; ++r)
      for (uint32_t c = 0; c < cols; ++c)
        if (inverse_mass[std::size_t{r} * cols + c] != uniform) {
          ColumnSpan& span = varied_columns_[r];
          span.begin = std::min(span.begin, c);
          span.end = std::max(span.end, c + 1);
        }
  }

  // The positions of colour `color`'s springs from `row` (from column col_begin) with an
  // end of another inverse mass: the hull of the start row's and the partner row's spans.
  std::pair<std::size_t, std::size_t> varied_positions(const GridColor& color, uint32_t row) const {
    const GridStencil& step = color.step();
    int64_t begin = std::numeric_limits<int64_t>::max(), end = 0;
    const auto add = [&](const ColumnSpan& span, int64_t start_column_offset) {
      if (span.begin >= span.end) return;
      begin = std::min(begin, int64_t{span.begin} - start_column_offset);
      end = std::max(end, int64_t{span.end} - start_column_offset);
    };
    add(varied_columns_[row], color.col_begin);
    add(varied_columns_[row + step.row_step], int64_t{color.col_begin} + step.col_step);
    if (begin >= end) return {0, 0};
    return {static_cast<std::size_t>(std::max<int64_t>(begin, 0)), static_cast<std::size_t>(end)};
  }

  // Two bands, one per half of the threads, when the rows hold both reserves (else one
  // band and the seam would be all of it); one band on one thread.
  Bands bands_of(int threads) const {
    if (threads < 2 || grid_->rows < 2 * band_reserve()) return {false, threads};
    return {true, (threads + 1) / 2};
  }

  // The rows a band holds from the start: one more than the wavefront's total lag, so that
  // every phase visits at least one row of each band and the seam below is all that is left.
  uint32_t band_reserve() const { return phases_.back().lag + 1; }

  // Phases [begin, end) of `thread` among `threads`: contiguous runs of about equal cost.
  std::pair<std::size_t, std::size_t> phases_of(int thread, int threads) const {
    uint64_t total = 0;
    for (const Phase& phase : phases_) total += phase.cost;
    std::size_t begin = phases_.size(), end = 0;
    uint64_t before = 0;
    for (std::size_t q = 0; q < phases_.size(); ++q) {
      const uint64_t middle = 2 * before + phases_[q].cost;  // twice the phase's midpoint
      const auto owner = static_cast<int>(
          std::min<uint64_t>(static_cast<uint64_t>(threads - 1),
                             middle * static_cast<uint64_t>(threads) / (2 * total)));
      if (owner == thread) begin = std::min(begin, q), end = q + 1;
      before += phases_[q].cost;
    }
    return {std::min(begin, end), end};
  }

  // This thread's phases over its band's wavefront, as long as the band claims rows, then
  // (each band's first thread, after all bands are done) the seam between the bands;
  // returns its share of "every velocity is finite".
  template <class Real>
  bool grid_sweep(const Substep<Real>& s, int thread, int threads) {
    const Bands bands = bands_of(threads);
    const uint32_t rows = grid_->rows;
    const bool upper = thread >= bands.lower_threads;
    const int member = upper ? thread - bands.lower_threads : thread;
    const int team = upper ? threads - bands.lower_threads : bands.lower_threads;
    const auto [begin, end] = phases_of(member, team);
    bool finite = true;
    uint32_t held = bands.two ? band_reserve() : rows;  // the band's rows, for its first thread
    uint32_t time = 0;
    for (;; ++time) {
      if (member > 0) {
        if (!wait_for(progress_[thread - 1], time)) break;
      } else if (time == held) {
        if (bands.two) held += claims_->claim();
        if (time == held) break;
      }
      for (std::size_t q = begin; q < end; ++q) {
        const Phase& phase = phases_[q];
        if (time < phase.lag) break;  // lags ascend: the later phases start later still
        run_phase(phase, upper ? rows - 1 - time + phase.upward_offset : time - phase.lag, s,
                  finite);
      }
      if (member + 1 < team && (time + 1) % publish_every_ == 0)
        progress_[thread].completed.store(time + 1, std::memory_order_release);
    }
    if (member + 1 < team) progress_[thread].end(time);
    if (threads > 1) {
#pragma omp barrier
    }
    // The lower band holds rows [0, boundary), the upper band the rest.
    if (thread == 0 || (bands.two && thread == bands.lower_threads))
      run_seam(s, bands.two, upper, upper ? rows - time : time, finite);
    return finite;
  }

  // The rows next to the boundary that neither wavefront reached, phase by phase. Two bands:
  // each band's first thread takes the rows on its side, and the two meet after each phase
  // (a phase's rows are independent; the next phase reads rows either may have written).
  // One band: thread 0 takes the last rows.
  template <class Real>
  void run_seam(const Substep<Real>& s, bool two_bands, bool upper, uint32_t boundary,
                bool& finite) {
    const int side = upper ? 1 : 0;
    for (std::size_t q = 0; q < phases_.size(); ++q) {
      const Phase& phase = phases_[q];
      const uint32_t first = upper ? boundary : boundary - std::min(boundary, phase.lag);
      const uint32_t last = !two_bands ? grid_->rows
                            : upper    ? boundary + phase.upward_offset
                                       : boundary;  // one past
      for (uint32_t row = first; row < last; ++row) run_phase(phase, row, s, finite);
      // A phase with no lag left no rows on either side: nothing to wait for.
      if (two_bands && q + 1 < phases_.size() && phase.lag > 0) {
        seam_progress_[side].completed.store(static_cast<uint32_t>(q + 1),
                                             std::memory_order_release);
        wait_for(seam_progress_[1 - side], static_cast<uint32_t>(q));
      }
    }
  }

  // One component of one row, in place: v becomes the substep's displacement
  // dx = h (v + h a); a pin's dx is 0 and its velocity waits in `pinned_velocity` (the
  // general path's displacement array, touched only at pins). Nothing reads v between this
  // phase and the velocity phase, and one array streams where v and dx were two. AllFree:
  // a run without pins, whose inverse masses need no reading.
  template <bool AllFree, class Real>
  static void predict_row(Real* __restrict v, Real* __restrict pinned_velocity,
                          const Real* __restrict a, const Real* __restrict inverse_mass,
                          std::size_t count, Real h) {
#pragma omp simd
    for (std::size_t i = 0; i < count; ++i) {
      const bool free = AllFree || inverse_mass[i] != 0;
      if (!free) pinned_velocity[i] = v[i];
      v[i] = free ? h * (v[i] + h * a[i]) : Real(0);
    }
  }

  // One component of one row: x += dx, v = dx / h on the free particles, where v holds dx
  // (a pin gets its velocity back, bit for bit); false if a velocity is not finite (all
  // exponent bits set): an integer OR vectorises where a flag or a sum would not.
  template <bool AllFree, class Real>
  static bool velocity_row(Real* __restrict x, Real* __restrict v,
                           const Real* __restrict pinned_velocity,
                           const Real* __restrict inverse_mass, std::size_t count, Real inverse_h) {
    using Bits = std::conditional_t<sizeof(Real) == 4, uint32_t, uint64_t>;
    constexpr Bits exponent = std::bit_cast<Bits>(std::numeric_limits<Real>::infinity());
    Bits non_finite = 0;
    for (std::size_t i = 0; i < count; ++i) {
      const bool free = AllFree || inverse_mass[i] != 0;
      const Real dx = v[i];
      const Real speed = free ? dx * inverse_h : pinned_velocity[i];
      x[i] = free ? x[i] + dx : x[i];
      v[i] = speed;
      non_finite |= free && (std::bit_cast<Bits>(speed) & exponent) == exponent;
    }
    return non_finite == 0;
  }

  // Calls run(begin, count, all_free) on the columns of `row` in up to three runs: before
  // and after its span of another inverse mass with std::true_type when the uniform one
  // is not 0 (no particle there is pinned), the span itself (or all) with std::false_type.
  template <class Run>
  void for_free_runs(uint32_t row, Run&& run) const {
    const uint32_t cols = grid_->cols;
    const ColumnSpan span = varied_columns_[row];
    if (uniform_weight_ == 0) {
      run(0, cols, std::false_type{});
      return;
    }
    if (span.begin >= span.end) {
      run(0, cols, std::true_type{});
      return;
    }
    if (span.begin > 0) run(0, span.begin, std::true_type{});
    run(span.begin, span.end - span.begin, std::false_type{});
    if (span.end < cols) run(span.end, cols - span.end, std::true_type{});
  }

  template <class Real>
  void run_phase(const Phase& phase, uint32_t row, const Substep<Real>& s, bool& finite) const {
    const std::size_t row_begin = std::size_t{row} * grid_->cols;
    switch (phase.kind) {
      case Phase::Kind::predict:
        for_free_runs(row, [&](std::size_t begin, std::size_t count, auto all_free) {
          for (std::size_t c = 0; c < 3; ++c) {
            const std::size_t e = c * s.stride + row_begin + begin;
            predict_row<decltype(all_free)::value>(s.v + e, s.displacement + e,
                                                   s.external_acceleration + e,
                                                   s.inverse_mass + row_begin + begin, count, s.h);
          }
        });
        return;
      case Phase::Kind::tether:
        // On the grid v holds the substep's displacement between predict and velocity.
        s.tethers->project(row_begin, row_begin + grid_->cols, s.x, s.v, s.inverse_mass, s.stride);
        return;
      case Phase::Kind::velocity: {
        bool bad = false;
        for_free_runs(row, [&](std::size_t begin, std::size_t count, auto all_free) {
          for (std::size_t c = 0; c < 3; ++c) {
            const std::size_t e = c * s.stride + row_begin + begin;
            bad |= !velocity_row<decltype(all_free)::value>(s.x + e, s.v + e, s.displacement + e,
                                                            s.inverse_mass + row_begin + begin,
                                                            count, s.inverse_h);
          }
        });
        finite = finite && !bad;
        return;
      }
      case Phase::Kind::project: {
        const GridColor& color = grid_->colors[phase.color];
        if (!color.starts_in_row(row)) return;
        const GridStencil& step = color.step();
        const auto [varied_begin, varied_end] = varied_positions(color, row);
        project_row(ColorRow<Real>{
            s.x, s.v, s.inverse_mass,
            s.lambda == nullptr ? nullptr : s.lambda + std::size_t{phase.color} * s.particle_count,
            s.stride, row_begin + color.col_begin, color.col_end - color.col_begin,
            static_cast<std::size_t>(int64_t{step.row_step} * grid_->cols + step.col_step),
            color.in_row(), step.col_step == 2 ? 1u : 0u, color.parity,
            static_cast<Real>(color.rest), static_cast<Real>(color.ks) * s.h_squared,
            static_cast<Real>(color.kd) * s.h, phase.iteration == 0,
            phase.iteration + 1 < static_cast<uint32_t>(iterations_),
            static_cast<Real>(uniform_weight_), varied_begin, varied_end});
        return;
      }
    }
  }

  // Predict, project colour by colour, update velocities. Returns this thread's share of
  // "every velocity is finite".
  template <class Real>
  bool sweep(const Substep<Real>& s) const {
    const auto n = static_cast<long>(s.particle_count);
#pragma omp for schedule(static)
    for (long i = 0; i < n; ++i)
      for (std::size_t c = 0; c < 3; ++c) {
        const std::size_t e = c * s.stride + static_cast<std::size_t>(i);
        s.displacement[e] = 0;  // pinned too: their dx must be 0
        if (s.inverse_mass[i] == 0) continue;
        s.displacement[e] = s.h * (s.v[e] + s.h * s.external_acceleration[e]);
      }
    for (int iteration = 0; iteration < iterations_; ++iteration)
      for (std::size_t color = 0; color + 1 < color_offsets_.size(); ++color) {
        const long begin = color_offsets_[color], end = color_offsets_[color + 1];
#pragma omp for schedule(static)
        for (long k = begin; k < end; ++k)
          project(s.constraints[k], s.lambda[k], iteration == 0, s.x, s.displacement, s.stride, s.h,
                  s.h_squared);
      }
    if (s.tethers != nullptr) {
      const long blocks = (n + tether_block - 1) / tether_block;
#pragma omp for schedule(static)
      for (long block = 0; block < blocks; ++block)
        s.tethers->project(static_cast<std::size_t>(block * tether_block),
                           static_cast<std::size_t>(std::min(n, (block + 1) * tether_block)), s.x,
                           s.displacement, s.inverse_mass, s.stride);
    }
    bool finite = true;
#pragma omp for schedule(static)
    for (long i = 0; i < n; ++i) {
      if (s.inverse_mass[i] == 0) continue;
      for (std::size_t c = 0; c < 3; ++c) {
        const std::size_t e = c * s.stride + static_cast<std::size_t>(i);
        s.x[e] += s.displacement[e];
        s.v[e] = s.displacement[e] * s.inverse_h;
        finite = finite && std::isfinite(s.v[e]);
      }
    }
    return finite;
  }

  template <class Real>
  // lambda is reset at the substep's first iteration (`fresh`), then accumulates.
  static void project(const Constraint<Real>& spring, Real& lambda, bool fresh, const Real* x,
                      Real* displacement, std::size_t stride, Real h, Real h_squared) {
    std::array<Real, 3> d, moved;
    for (std::size_t c = 0; c < 3; ++c) {
      const std::size_t i = c * stride + spring.first, j = c * stride + spring.second;
      moved[c] = displacement[i] - displacement[j];
      d[c] = (x[i] - x[j]) + moved[c];
    }
    const Real accumulated = fresh ? Real(0) : lambda;
    lambda = accumulated;
    const Real length = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    if (!(length > 0)) return;  // coincident ends: no direction to push along
    const Real inverse_length = 1 / length;
    const Real stiffness = spring.ks * h_squared, damping = spring.kd * h;
    const Real closing = (d[0] * moved[0] + d[1] * moved[1] + d[2] * moved[2]) * inverse_length;
    const Real delta = (-stiffness * (length - spring.rest) - lambda - damping * closing) /
                       ((stiffness + damping) * (spring.first_weight + spring.second_weight) + 1);
    lambda += delta;
    const Real push_first = spring.first_weight * delta * inverse_length;
    const Real push_second = spring.second_weight * delta * inverse_length;
    for (std::size_t c = 0; c < 3; ++c) {
      const std::size_t i = c * stride + spring.first, j = c * stride + spring.second;
      if (spring.first_weight != 0) {
        displacement[i] += push_first * d[c];
      }
      if (spring.second_weight != 0) {
        displacement[j] -= push_second * d[c];
      }
    }
  }

  int substeps_;
  int iterations_;
  int requested_threads_;
  uint32_t tethers_per_particle_;
  double tether_slack_;
  int threads_ = 1;
  Constraints<float> constraints_f32_;
  Constraints<double> constraints_f64_;
  Tethers<float> tethers_f32_;
  Tethers<double> tethers_f64_;
  std::vector<uint32_t> color_offsets_;  // constraints of colour c: [offsets[c], offsets[c + 1])
  ScratchVectors<2> scratch_;            // external acceleration, the substep's displacement
  std::optional<GridLayout> grid_;       // the fast path's grid, when the topology is one
  std::vector<Phase> phases_;
  double uniform_weight_ = 0;               // the grid's common inverse mass (exact in Real)
  std::vector<ColumnSpan> varied_columns_;  // per grid row: the columns of another
  uint32_t publish_every_ = 1;              // wavefront times between a thread's progress stores
  std::unique_ptr<Progress[]> progress_;    // one per thread
  std::unique_ptr<RowClaims> claims_ = std::make_unique<RowClaims>();  // the two bands' rows
  // The seam's phases done by each band's first thread, the lower band's first.
  std::unique_ptr<Progress[]> seam_progress_ = std::make_unique<Progress[]>(2);
};

}  // namespace clothlab::builtin

CLOTHLAB_PLUGIN_ENTRY(clothlab::builtin::tethered_build ? "clothlab-builtin-xpbd-tethers"
                                                        : "clothlab-builtin-xpbd",
                      "1.1.0", clothlab::sdk::integrators<clothlab::builtin::Xpbd>,
                      clothlab::sdk::scenarios<>)
