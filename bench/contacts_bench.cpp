// The cost of keeping the cloth out of its colliders (clothlab.contacts/1: the host sets the
// colliders' poses at the step's start, then resolves each particle's path after each step or
// substep) beside one force evaluation of the same cloth, in one run: the ratio is what a
// collider scene adds to a method's step. On the drape's defaults (50 x 50 cotton-like square,
// float32) settled for 2 s by xpbd over its sphere and over its table, and the same cloth over a
// horizontal capsule (an arm); the states are where contacts are busiest: resting on the body.
// Run by hand: build/bin/clothlab_contacts_bench (lab/performance.md, "Contacts").
#include <benchmark/benchmark.h>
#include <clothlab/ext/contacts.h>

#include <clothlab/core/cloth.hpp>
#include <cstdlib>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "bench_setup.hpp"

namespace clothlab::bench {
namespace {

enum Support { kSphere, kTable, kCapsule };

std::vector<Collider> support_colliders(Support support) {
  if (support != kCapsule)
    return make_colliders("drape", {{"support", support == kSphere ? "0" : "1"}});
  Collider arm;
  arm.shape = ColliderShape::Capsule;
  arm.radius = 0.08;
  arm.end_radius = 0.06;
  arm.half_length = 0.4;
  arm.friction = 0.5;
  arm.thickness = 0.005;
  arm.pose.position = {0, -0.08, 0};
  return {arm};
}

// The drape's cloth settled over its support, shared by the benchmarks of that support.
struct Settled {
  explicit Settled(Support support)
      : colliders(support_colliders(support)),
        cloth(make_scene("drape", ParamTexts{}), Precision::Float32, PipelineOptions{true, 1}) {
    BoundIntegrator xpbd("xpbd", cloth, {{"threads", "1"}});
    constexpr double dt = 1.0 / 60.0;
    for (int step = 0; step < 120; ++step) {
      cloth.set_colliders(colliders, 0.0);
      xpbd.step(step * dt, dt);
    }
    cloth.set_colliders(colliders, 0.0);
    acceleration = static_cast<float*>(cloth.system().alloc_vector(cloth.system().context));
  }
  std::vector<Collider> colliders;
  Cloth cloth;
  float* acceleration = nullptr;
};

Settled& settled(Support support) {
  static std::map<Support, std::unique_ptr<Settled>> clothes;
  auto& slot = clothes[support];
  if (!slot) slot = std::make_unique<Settled>(support);
  return *slot;
}

void force_evaluation(benchmark::State& state, Support support) {
  Settled& drape = settled(support);
  const clothlab_system& system = drape.cloth.system();
  for (auto _ : state) {
    system.eval_acceleration(system.context, 0.0, system.x, system.v, drape.acceleration);
    benchmark::ClobberMemory();
  }
}

// What the host and an integrator do for contacts in a step: set the poses (which also marks
// where each particle's path starts), then resolve the cloth against them.
void contact_resolution(benchmark::State& state, Support support) {
  Settled& drape = settled(support);
  const clothlab_system& system = drape.cloth.system();
  const auto* contacts = static_cast<const clothlab_contacts_extension*>(
      clothlab_system_extension(&system, CLOTHLAB_EXT_CONTACTS));
  for (auto _ : state) {
    drape.cloth.set_colliders(drape.colliders, 0.0);
    contacts->resolve(system.context, 0.0, system.x, system.v);
    benchmark::ClobberMemory();
  }
  const Cloth::Contacts now = drape.cloth.contacts();
  state.counters["inside"] = now.particles_inside;
}

BENCHMARK_CAPTURE(force_evaluation, sphere, kSphere)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(contact_resolution, sphere, kSphere)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(force_evaluation, table, kTable)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(contact_resolution, table, kTable)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(force_evaluation, capsule, kCapsule)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(contact_resolution, capsule, kCapsule)->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace clothlab::bench

BENCHMARK_MAIN();
