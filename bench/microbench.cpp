// Google Benchmark microbenchmarks: each force stage and a whole step per integrator,
// fast core vs the seed-style reference, over mesh sizes 50^2 ... 1000^2 (float32); and the
// cost units of the implicit and position-based methods at 300 x 300 on 1 and 2 threads
// beside one explicit force evaluation: an iteration of implicit_euler's CG and an XPBD
// substep. Run by hand (tools/bench.sh --micro); never part of CTest timing.
#include <benchmark/benchmark.h>
#include <clothlab/ext/jacobian.h>
#include <clothlab/ext/reductions.h>

#include <array>
#include <chrono>
#include <clothlab/core/cloth.hpp>
#include <clothlab/sdk.hpp>
#include <cstdlib>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "bench_setup.hpp"
#include "preconditioned_cg.hpp"
#include "reference_forces.hpp"

namespace clothlab::bench {
namespace {

constexpr int kSides[] = {50, 100, 200, 300, 500, 1000};

Scene bench_scene(const std::string& scenario, int side, bool with_springs) {
  ParamTexts params = bench_cloth_params(side);
  if (!with_springs) {
    for (const char* family : {"structural", "shear", "flexion"}) {
      params.emplace_back(std::string(family) + ".ks", "0");
      params.emplace_back(std::string(family) + ".kd", "0");
    }
  }
  return make_scene(scenario, params);
}

struct FreeDeleter {
  void operator()(float* data) const { std::free(data); }
};
using AlignedFloats = std::unique_ptr<float[], FreeDeleter>;

AlignedFloats aligned_floats(std::size_t count) {
  const std::size_t bytes = (count * sizeof(float) + 63) / 64 * 64;
  auto* data = static_cast<float*>(std::aligned_alloc(64, bytes));
  if (data == nullptr) throw std::bad_alloc();
  std::fill_n(data, bytes / sizeof(float), 0.0f);
  return AlignedFloats(data);
}

void set_rates(benchmark::State& state, uint64_t springs_per_iteration) {
  state.counters["springs_per_s"] = benchmark::Counter(
      static_cast<double>(springs_per_iteration), benchmark::Counter::kIsIterationInvariantRate);
  state.counters["particles_per_s"] =
      benchmark::Counter(static_cast<double>(state.range(0)) * static_cast<double>(state.range(0)),
                         benchmark::Counter::kIsIterationInvariantRate);
}

// One fast acceleration evaluation: the stages the scene and `damped` call for.
void fast_forces(benchmark::State& state, const std::string& scenario, bool with_springs,
                 bool damped) {
  const int side = static_cast<int>(state.range(0));
  const Scene scene = bench_scene(scenario, side, with_springs);
  Cloth cloth(scene, Precision::Float32, PipelineOptions{damped, 0});
  const clothlab_system& system = cloth.system();
  AlignedFloats a = aligned_floats(3 * std::size_t{system.stride});
  for (auto _ : state) {
    system.eval_acceleration(system.context, 0.0, system.x, damped ? system.v : nullptr, a.get());
    benchmark::ClobberMemory();
  }
  set_rates(state, with_springs ? cloth.springs().total() : 0);
}

// The seed-style evaluation: spring structs, scatter-add, one thread, particle-major.
void reference_forces(benchmark::State& state, const std::string& scenario, bool with_springs,
                      bool damped) {
  const int side = static_cast<int>(state.range(0));
  reference::ReferenceCloth<float> cloth(bench_scene(scenario, side, with_springs));
  const std::vector<float> x = cloth.initial_positions();
  const std::vector<float> v(x.size(), 0.0f);
  std::vector<float> a(x.size());
  for (auto _ : state) {
    cloth.acceleration(x.data(), damped ? v.data() : nullptr, a.data());
    benchmark::ClobberMemory();
  }
  set_rates(state, with_springs ? cloth.springs().size() : 0);
}

// A whole step of integrator `id` on the flag, restarted from rest if it ever diverges.
void fast_step(benchmark::State& state, const std::string& id) {
  const int side = static_cast<int>(state.range(0));
  const Scene scene = bench_scene("flag", side, true);
  Cloth cloth(scene, Precision::Float32, PipelineOptions{integrator_uses_velocity_forces(id), 0});
  std::vector<double> x0, v0;
  cloth.positions(x0);
  cloth.velocities(v0);
  BoundIntegrator integrator(id, cloth);
  const uint64_t evals_before = cloth.counters().force_evals;
  double t = 0.0;
  for (auto _ : state) {
    try {
      integrator.step(t, 1e-3);
      t += 1e-3;
    } catch (const std::exception&) {
      state.PauseTiming();
      cloth.set_state(x0, v0);
      integrator = BoundIntegrator(id, cloth);
      state.ResumeTiming();
    }
  }
  const double evals_per_step = static_cast<double>(cloth.counters().force_evals - evals_before) /
                                static_cast<double>(state.iterations());
  set_rates(state,
            static_cast<uint64_t>(evals_per_step * static_cast<double>(cloth.springs().total())));
  state.counters["real_time_factor"] =
      benchmark::Counter(1e-3, benchmark::Counter::kIsIterationInvariantRate);
}

// The baseline step: reference forces, then the same semi-implicit Euler update.
void reference_euler_step(benchmark::State& state) {
  const int side = static_cast<int>(state.range(0));
  reference::ReferenceCloth<float> cloth(bench_scene("flag", side, true));
  std::vector<float> x = cloth.initial_positions();
  std::vector<float> v(x.size(), 0.0f);
  std::vector<float> a(x.size());
  const float dt = 1e-3f;
  for (auto _ : state) {
    cloth.acceleration(x.data(), v.data(), a.data());
    for (std::size_t i = 0; i < x.size(); ++i) {
      v[i] += dt * a[i];
      x[i] += dt * v[i];
    }
    benchmark::ClobberMemory();
  }
  set_rates(state, cloth.springs().size());
  state.counters["real_time_factor"] =
      benchmark::Counter(1e-3, benchmark::Counter::kIsIterationInvariantRate);
}

// One damped explicit acceleration evaluation of the flag (side x side) at rest: the unit the
// implicit and position-based costs are compared with.
class ForceEvaluation {
 public:
  ForceEvaluation(int side, int threads)
      : cloth_(bench_scene("flag", side, true), Precision::Float32, PipelineOptions{true, threads}),
        acceleration_(aligned_floats(3 * std::size_t{cloth_.system().stride})) {}
  void run() {
    const clothlab_system& system = cloth_.system();
    system.eval_acceleration(system.context, 0.0, system.x, system.v, acceleration_.get());
    benchmark::ClobberMemory();
  }

 private:
  Cloth cloth_;
  AlignedFloats acceleration_;
};

// One XPBD substep (inner_substeps = 1, one iteration: predict, 12 colour sweeps, velocities) of
// the flag, the plugin and the host on `threads` threads.
class XpbdSubstep {
 public:
  XpbdSubstep(int side, int threads)
      : cloth_(bench_scene("flag", side, true), Precision::Float32, PipelineOptions{true, threads}),
        xpbd_(
            "xpbd", cloth_,
            {{"inner_substeps", "1"}, {"iterations", "1"}, {"threads", std::to_string(threads)}}) {}
  void run() {
    xpbd_.step(t_, 1e-3);
    t_ += 1e-3;
  }

 private:
  Cloth cloth_;
  BoundIntegrator xpbd_;
  double t_ = 0.0;
};

// A force evaluation of the 300 x 300 flag on state.range(1) threads.
void force_evaluation(benchmark::State& state) {
  ForceEvaluation forces(static_cast<int>(state.range(0)), static_cast<int>(state.range(1)));
  for (auto _ : state) forces.run();
}

// implicit_euler's CG (preconditioned_cg.hpp, the plugin's own code, definite matrix as the
// plugin's default, fused host sweeps where offered and `fused`) on the 300 x 300 flag at
// h = 1/60 s from rest, right-hand side h a0, on state.range(1) threads.
class CgSolve {
 public:
  CgSolve(benchmark::State& state, bool fused)
      : CgSolve(static_cast<int>(state.range(0)), static_cast<int>(state.range(1)), fused) {}
  CgSolve(int side, int threads, bool fused)
      : cloth_(bench_scene("flag", side, true), Precision::Float32, PipelineOptions{true, threads}),
        system_(cloth_.system()) {
    system_.jacobian().reserve();
    for (float*& vector : vectors_) vector = system_.alloc_vector();
    rhs_ = system_.alloc_vector();
    solution_ = system_.alloc_vector();
    zero_ = system_.alloc_vector();
    inverse_blocks_.resize(9 * std::size_t{system_.particle_count()});
    solver_.emplace(system_, vectors_, inverse_blocks_, true, fused);
    system_.acceleration(0.0, system_.x(), system_.v(), rhs_);
    system_.template lincomb<1>(rhs_, zero_, {kStep}, {rhs_});
  }
  bool fused() const { return solver_->fused(); }
  // A solve from 0: the matrix fixed at the state (cg-step's linearise where fused), the
  // preconditioner, the first residual and direction.
  void start() {
    system_.copy(solution_, zero_);
    solver_->start(0.0, kStep, system_.x(), system_.v(), rhs_, solution_, false, 0.0);
  }
  builtin::PreconditionedCg<float>& solver() { return *solver_; }
  // One iteration; false once CG has stopped.
  bool iterate() {
    const bool running = solver_->iterate() == builtin::PreconditionedCg<float>::Outcome::kRunning;
    benchmark::ClobberMemory();
    return running;
  }
  sdk::CgStep<float> cg_step() const { return system_.cg_step(); }
  // The solver's r, z, p, q and the two preconditioner vectors, as started.
  float* vector(std::size_t index) const { return vectors_[index]; }
  float* solution() const { return solution_; }

 private:
  static constexpr double kStep = 1.0 / 60.0;
  Cloth cloth_;
  sdk::System<float> system_;
  std::array<float*, builtin::PreconditionedCg<float>::vector_count> vectors_{};
  float *rhs_ = nullptr, *solution_ = nullptr, *zero_ = nullptr;
  std::vector<double> inverse_blocks_;
  std::optional<builtin::PreconditionedCg<float>> solver_;
};

// One CG iteration. A genuine solve, restarted every 20 iterations outside the timing (the
// stiff cloth takes hundreds to converge, so none of the 20 is idle). fused = 0 runs the same
// iteration through the separate host calls.
void cg_iteration(benchmark::State& state, bool fused) {
  CgSolve solve(state, fused);
  if (fused && !solve.fused()) {
    state.SkipWithError("the host lacks clothlab.cg-step/1");
    return;
  }
  solve.start();
  int iteration = 0;
  for (auto _ : state) {
    if (++iteration % 20 == 0) {
      state.PauseTiming();
      solve.start();
      state.ResumeTiming();
    }
    if (!solve.iterate()) {
      state.SkipWithError("CG stopped within 20 iterations");
      return;
    }
  }
}

// cg_iteration's two host sweeps apart (clothlab.cg-step/1, after a start): `product` with the
// direction update riding on it (alpha = 0, beta = 0: p = z, so repeats see the same input),
// and `update` (alpha = 0: r stays).
void cg_sweep(benchmark::State& state, bool product) {
  CgSolve solve(state, true);
  if (!solve.fused()) {
    state.SkipWithError("the host lacks clothlab.cg-step/1");
    return;
  }
  solve.start();
  const sdk::CgStep<float> step = solve.cg_step();
  float *r = solve.vector(0), *z = solve.vector(1), *p = solve.vector(2), *q = solve.vector(3);
  for (auto _ : state) {
    if (product) {
      benchmark::DoNotOptimize(step.product(0.0, 0.0, z, p, solve.solution(), q));
    } else {
      benchmark::DoNotOptimize(step.update(0.0, q, solve.vector(4), solve.vector(5), r, z));
    }
    benchmark::ClobberMemory();
  }
}

// What a solve costs once before its iterations (what cg_iteration leaves out).
void cg_start(benchmark::State& state, bool fused) {
  CgSolve solve(state, fused);
  for (auto _ : state) {
    solve.start();
    benchmark::ClobberMemory();
  }
}

// One Jacobian product alone (c_x = h^2, c_v = h, damped): the main part of a CG iteration.
void jacobian_product(benchmark::State& state) {
  const Scene scene = bench_scene("flag", static_cast<int>(state.range(0)), true);
  Cloth cloth(scene, Precision::Float32, PipelineOptions{true, static_cast<int>(state.range(1))});
  const clothlab_system& system = cloth.system();
  const auto* jacobian = static_cast<const clothlab_jacobian_extension*>(
      system.get_extension(system.context, CLOTHLAB_EXT_JACOBIAN));
  if (jacobian == nullptr || jacobian->reserve(system.context) != 0) {
    state.SkipWithError("the host lacks the jacobian extension");
    return;
  }
  const std::size_t size = 3 * std::size_t{system.stride};
  AlignedFloats p = aligned_floats(size), q = aligned_floats(size);
  for (std::size_t k = 0; k < size; ++k) p[k] = 1e-3f * static_cast<float>(k % 7);
  const double h = 1e-3;
  for (auto _ : state) {
    jacobian->apply(system.context, 0.0, system.x, system.v, h * h, h, p.get(), q.get());
    benchmark::ClobberMemory();
  }
}

// One XPBD substep of the flag on state.range(1) threads.
void xpbd_substep(benchmark::State& state) {
  XpbdSubstep xpbd(static_cast<int>(state.range(0)), static_cast<int>(state.range(1)));
  for (auto _ : state) xpbd.run();
}

// One substep as part of a step of 40 inner substeps (the per-step work, the tethers'
// anchors and a constant external acceleration, shared out): beside xpbd_substep, what a
// step's substeps cost more or less than one alone.
void xpbd_substep_in_step(benchmark::State& state) {
  const Scene scene = bench_scene("flag", static_cast<int>(state.range(0)), true);
  const int threads = static_cast<int>(state.range(1));
  Cloth cloth(scene, Precision::Float32, PipelineOptions{true, threads});
  constexpr int substeps = 40;
  BoundIntegrator xpbd("xpbd", cloth,
                       {{"inner_substeps", std::to_string(substeps)},
                        {"iterations", "1"},
                        {"threads", std::to_string(threads)}});
  double t = 0.0;
  for (auto _ : state) {
    xpbd.step(t, substeps * 1e-3);
    t += substeps * 1e-3;
  }
  // Seconds per substep: the step's time over its substeps.
  state.counters["s_per_substep"] = benchmark::Counter(
      substeps, benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}

// One XPBD substep of 32 sweeps of the flag on one thread: state.range(1) 0 plain (the grid
// path), 1 Chebyshev-accelerated with rho 0.95 (the general path), 2 the same with a delay past
// the last sweep (the general path and its saved iterates, every weight 1). A sweep's cost with
// and without the acceleration (lab/real-cloth.md, "Chebyshev acceleration of xpbd").
void xpbd_chebyshev_substep(benchmark::State& state) {
  const int variant = static_cast<int>(state.range(1));
  Cloth cloth(bench_scene("flag", static_cast<int>(state.range(0)), true), Precision::Float32,
              PipelineOptions{true, 1});
  BoundIntegrator xpbd("xpbd", cloth,
                       {{"inner_substeps", "1"},
                        {"iterations", "32"},
                        {"threads", "1"},
                        {"chebyshev_rho", variant == 0 ? "0" : "0.95"},
                        {"chebyshev_delay", variant == 2 ? "1000" : "10"}});
  double t = 0.0;
  for (auto _ : state) {
    xpbd.step(t, 1e-3);
    t += 1e-3;
  }
}

// The cost units on one thread count, each on a cloth of its own: a force evaluation, an
// XPBD substep and a CG iteration (as cg_iteration/fused, its solve started again before each
// block: the stiff cloth takes hundreds of iterations).
struct CostUnits {
  CostUnits(int side, int threads)
      : forces(side, threads), xpbd(side, threads), solve(side, threads, true) {}
  ForceEvaluation forces;
  XpbdSubstep xpbd;
  CgSolve solve;
};

// The cost units on 1 and 2 threads, paired in time: blocks of each unit on each thread
// count, alternated. Each block's first call is not timed (it finds the other blocks' data
// in the caches, and on 2 threads wakes the team). The counters are ratios of summed times,
// so a drift of the machine's speed between separate benchmarks (a shared machine) cancels: per
// thread count the XPBD substep and the CG iteration per force evaluation, and each unit's
// speedup from 1 to 2 threads.
void cost_units(benchmark::State& state) {
  constexpr int timed_per_block = 8;
  const int side = static_cast<int>(state.range(0));
  std::array<CostUnits, 2> units{CostUnits(side, 1), CostUnits(side, 2)};
  if (!units[0].solve.fused() || !units[1].solve.fused()) {
    state.SkipWithError("the host lacks clothlab.cg-step/1");
    return;
  }
  using Clock = std::chrono::steady_clock;
  enum Unit { kForce, kXpbd, kCg, kUnits };
  std::array<std::array<Clock::duration, kUnits>, 2> time{};
  const auto block = [](Clock::duration& total, auto&& call) {
    call();
    const Clock::time_point start = Clock::now();
    for (int k = 0; k < timed_per_block; ++k) call();
    total += Clock::now() - start;
  };
  bool cg_running = true;
  for (auto _ : state) {
    for (std::size_t t = 0; t < 2; ++t) {
      CostUnits& u = units[t];
      block(time[t][kForce], [&] { u.forces.run(); });
      block(time[t][kXpbd], [&] { u.xpbd.run(); });
      u.solve.start();
      block(time[t][kCg], [&] { cg_running &= u.solve.iterate(); });
    }
  }
  if (!cg_running) {
    state.SkipWithError("CG stopped within a block's iterations");
    return;
  }
  const auto seconds = [&](std::size_t t, Unit unit) {
    return std::chrono::duration<double>(time[t][unit]).count();
  };
  for (std::size_t t = 0; t < 2; ++t) {
    const std::string threads = std::to_string(t + 1) + "t";
    state.counters["xpbd_per_force_" + threads] = seconds(t, kXpbd) / seconds(t, kForce);
    state.counters["cg_per_force_" + threads] = seconds(t, kCg) / seconds(t, kForce);
    state.counters["force_us_" + threads] =
        1e6 * seconds(t, kForce) / (timed_per_block * static_cast<double>(state.iterations()));
  }
  state.counters["force_speedup"] = seconds(0, kForce) / seconds(1, kForce);
  state.counters["xpbd_speedup"] = seconds(0, kXpbd) / seconds(1, kXpbd);
  state.counters["cg_speedup"] = seconds(0, kCg) / seconds(1, kCg);
}

void at_300_on_1_and_2_threads(benchmark::internal::Benchmark* benchmark) {
  for (int threads : {1, 2}) benchmark->Args({300, threads});
  benchmark->Unit(benchmark::kMicrosecond)->UseRealTime();
}

// A step of `id` on a sheet of rows x cols particles, one thread: a tall and a wide strip of the
// same springs cost the same (the pipeline streams rows; a one-column grid goes as one row).
void strip_step(benchmark::State& state, const std::string& id) {
  const auto rows = static_cast<uint32_t>(state.range(0));
  const auto cols = static_cast<uint32_t>(state.range(1));
  const Scene scene =
      make_scene("sheet", {{"rows", std::to_string(rows)}, {"cols", std::to_string(cols)}});
  Cloth cloth(scene, Precision::Float32, PipelineOptions{integrator_uses_velocity_forces(id), 1});
  BoundIntegrator integrator(id, cloth);
  double t = 0.0;
  for (auto _ : state) {
    integrator.step(t, 1e-4);
    t += 1e-4;
  }
  state.counters["springs_per_s"] = benchmark::Counter(
      static_cast<double>(cloth.springs().total()), benchmark::Counter::kIsIterationInvariantRate);
}

void strips(benchmark::internal::Benchmark* benchmark) {
  for (const auto& [rows, cols] :
       {std::pair{4096, 1}, {1, 4096}, {4096, 2}, {2, 4096}, {4096, 8}, {8, 4096}})
    benchmark->Args({rows, cols});
  benchmark->Unit(benchmark::kMicrosecond)->UseRealTime();
}

void sizes(benchmark::internal::Benchmark* benchmark) {
  for (int side : kSides) benchmark->Arg(side);
  benchmark->Unit(benchmark::kMicrosecond)->UseRealTime();
}

BENCHMARK_CAPTURE(fast_forces, springs_damped, std::string("sheet"), true, true)->Apply(sizes);
BENCHMARK_CAPTURE(fast_forces, springs_undamped, std::string("sheet"), true, false)->Apply(sizes);
BENCHMARK_CAPTURE(fast_forces, gravity_only, std::string("sheet"), false, false)->Apply(sizes);
BENCHMARK_CAPTURE(fast_forces, wind_and_gravity, std::string("flag"), false, false)->Apply(sizes);
BENCHMARK_CAPTURE(fast_forces, flag_all, std::string("flag"), true, true)->Apply(sizes);
BENCHMARK_CAPTURE(reference_forces, springs_damped, std::string("sheet"), true, true)->Apply(sizes);
BENCHMARK_CAPTURE(reference_forces, springs_undamped, std::string("sheet"), true, false)
    ->Apply(sizes);
BENCHMARK_CAPTURE(reference_forces, wind_and_gravity, std::string("flag"), false, false)
    ->Apply(sizes);
BENCHMARK_CAPTURE(reference_forces, flag_all, std::string("flag"), true, true)->Apply(sizes);
BENCHMARK_CAPTURE(fast_step, euler, std::string("euler"))->Apply(sizes);
BENCHMARK_CAPTURE(fast_step, verlet, std::string("verlet"))->Apply(sizes);
BENCHMARK_CAPTURE(fast_step, midpoint, std::string("midpoint"))->Apply(sizes);
BENCHMARK_CAPTURE(fast_step, rk4, std::string("rk4"))->Apply(sizes);
BENCHMARK(reference_euler_step)->Apply(sizes);
BENCHMARK(force_evaluation)->Apply(at_300_on_1_and_2_threads);
BENCHMARK(jacobian_product)->Apply(at_300_on_1_and_2_threads);
BENCHMARK_CAPTURE(cg_iteration, fused, true)->Apply(at_300_on_1_and_2_threads);
BENCHMARK_CAPTURE(cg_iteration, separate_calls, false)->Apply(at_300_on_1_and_2_threads);
BENCHMARK_CAPTURE(cg_sweep, product, true)->Apply(at_300_on_1_and_2_threads);
BENCHMARK_CAPTURE(cg_sweep, update, false)->Apply(at_300_on_1_and_2_threads);
BENCHMARK_CAPTURE(cg_start, fused, true)->Apply(at_300_on_1_and_2_threads);
BENCHMARK_CAPTURE(cg_start, separate_calls, false)->Apply(at_300_on_1_and_2_threads);
BENCHMARK(xpbd_substep)->Apply(at_300_on_1_and_2_threads);
BENCHMARK(xpbd_substep_in_step)->Apply(at_300_on_1_and_2_threads);
BENCHMARK(xpbd_chebyshev_substep)->Args({100, 0})->Args({100, 1})->Args({100, 2});
BENCHMARK(cost_units)->Arg(300)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(strip_step, rk4, std::string("rk4"))->Apply(strips);
BENCHMARK_CAPTURE(strip_step, verlet, std::string("verlet"))->Apply(strips);

}  // namespace
}  // namespace clothlab::bench

BENCHMARK_MAIN();
