// robustness.*: no exception crosses the C boundary, step never touches the heap (in any
// thread, and not through the host's prepare-only calls), and instances on separate cloths do
// not interfere.
#include <clothlab/core/collider.hpp>
#include <exception>
#include <string>
#include <thread>
#include <vector>

#include "allocation_counter.hpp"
#include "check.hpp"
#include "fixtures.hpp"
#include "plugin_only_system.hpp"

namespace clothlab::conformance {
namespace {

constexpr int measured_steps = 10;
constexpr int concurrent_steps = 50;

// Calls `call` through the raw ABI and fails if any exception comes out of it.
template <class Call>
void require_no_escape(const std::string& what, Call&& call) {
  try {
    call();
  } catch (const std::exception& e) {
    throw CheckFailure("an exception escaped the C boundary from " + what + ": " + e.what());
  } catch (...) {
    throw CheckFailure("an exception escaped the C boundary from " + what);
  }
}

Verdict nothing_escapes(const clothlab_integrator& integrator, SheetShape shape) {
  Values values = default_values(integrator);
  Cloth cloth = sheet_cloth(sheet_scene(4, 4, true), shape, preferred_precision(integrator),
                            pipeline_for(integrator));
  clothlab_message message{};
  void* instance = nullptr;
  require_no_escape("create", [&] {
    integrator.create(values.data(), integrator.param_count, &instance, &message);
  });
  require(instance != nullptr, "create with default values failed: " + std::string(message.text));
  struct Destroy {
    const clothlab_integrator& integrator;
    void* instance;
    ~Destroy() { integrator.destroy(instance); }
  } destroy{integrator, instance};
  require_no_escape("prepare", [&] { integrator.prepare(instance, &cloth.system(), &message); });
  for (int i = 0; i < 3; ++i)
    require_no_escape(
        "step", [&] { integrator.step(instance, &cloth.system(), i * 1e-3, 1e-3, &message); });
  require_no_escape("step with dt = -1",
                    [&] { integrator.step(instance, &cloth.system(), 0.0, -1.0, &message); });
  values.push_back({});
  void* extra = nullptr;
  require_no_escape("create with too many values", [&] {
    if (integrator.create(values.data(), static_cast<uint32_t>(values.size()), &extra, &message) ==
        CLOTHLAB_OK)
      integrator.destroy(extra);
  });
  return {true, ""};
}

// A sphere through the middle of the 1 m x 0.8 m sheet: several particles start inside it.
Collider sphere_through_the_middle(const Cloth& cloth) {
  std::vector<double> x;
  cloth.positions(x);
  Collider sphere;
  sphere.shape = ColliderShape::Sphere;
  sphere.radius = 0.2;
  sphere.thickness = 0.002;
  sphere.friction = 0.5;
  for (std::size_t i = 0; i < x.size(); ++i) sphere.pose.position[i % 3] += 3 * x[i] / x.size();
  return sphere;
}

Verdict step_does_not_allocate(const clothlab_integrator& integrator, SheetShape shape) {
  Cloth cloth = sheet_cloth(sheet_scene(8, 8, true), shape, preferred_precision(integrator),
                            pipeline_for(integrator));
  // An integrator that resolves contacts meets a collider, so its contact path is measured.
  const bool contacts = has_trait(integrator, CLOTHLAB_TRAIT_RESOLVES_CONTACTS);
  const Collider sphere = sphere_through_the_middle(cloth);
  if (contacts) cloth.set_colliders({&sphere, 1}, 0.0);
  PluginOnlySystem measured(cloth.system());
  IntegratorInstance instance(integrator, default_values(integrator));
  clothlab_message message{};
  const clothlab_status prepared =
      integrator.prepare(instance.handle(), &measured.system(), &message);
  require(prepared == CLOTHLAB_OK, "prepare failed: " + describe_status(prepared, message));
  measured.close_prepare();
  uint64_t calls = 0;
  for (int i = 0; i < measured_steps; ++i) {
    allocations::arm();
    const clothlab_status status =
        integrator.step(instance.handle(), &measured.system(), i * 1e-3, 1e-3, &message);
    calls += allocations::disarm();
    require(measured.misuse().empty(),
            "in step " + std::to_string(i + 1) + ": " + measured.misuse());
    require(status == CLOTHLAB_OK, "step failed: " + describe_status(status, message));
  }
  require(calls == 0, std::to_string(calls) + " heap allocator calls during " +
                          std::to_string(measured_steps) + " steps");
  return {true, "0 allocator calls by the plugin in " + std::to_string(measured_steps) + " steps" +
                    (contacts ? " against a sphere" : "")};
}

// Two live instances stepped by turns in one thread: state shared between instances (a static)
// shows here every time, where two threads show it only when their steps happen to overlap.
void require_interleaved_equal(const clothlab_integrator& integrator, SheetShape shape,
                               const Scene (&scenes)[2], const State (&sequential)[2]) {
  const Precision precision = preferred_precision(integrator);
  Cloth cloths[2] = {sheet_cloth(scenes[0], shape, precision, pipeline_for(integrator)),
                     sheet_cloth(scenes[1], shape, precision, pipeline_for(integrator))};
  IntegratorInstance first(integrator, default_values(integrator));
  IntegratorInstance second(integrator, default_values(integrator));
  IntegratorInstance* instances[2] = {&first, &second};
  for (int i = 0; i < 2; ++i) instances[i]->prepare(cloths[i]);
  for (int n = 0; n < concurrent_steps; ++n)
    for (int i = 0; i < 2; ++i) instances[i]->step(cloths[i], n * 1e-3, 1e-3);
  for (int i = 0; i < 2; ++i)
    require(state_of(cloths[i]) == sequential[i],
            "instance " + std::to_string(i + 1) +
                " stepped by turns with another differs from its run alone");
}

Verdict concurrent_equals_sequential(const clothlab_integrator& integrator, SheetShape shape) {
  const Scene scenes[2] = {sheet_scene(16, 12, true), sheet_scene(12, 16)};
  State sequential[2], concurrent[2];
  for (int i = 0; i < 2; ++i)
    sequential[i] = simulate(integrator, scenes[i], preferred_precision(integrator), 1,
                             concurrent_steps, 1e-3, shape);
  require_interleaved_equal(integrator, shape, scenes, sequential);
  std::string errors[2];
  std::thread workers[2];
  for (int i = 0; i < 2; ++i)
    workers[i] = std::thread([&, i] {
      try {
        concurrent[i] = simulate(integrator, scenes[i], preferred_precision(integrator), 1,
                                 concurrent_steps, 1e-3, shape);
      } catch (const std::exception& e) {
        errors[i] = e.what();
      }
    });
  for (std::thread& worker : workers) worker.join();
  for (int i = 0; i < 2; ++i) {
    require(errors[i].empty(), "concurrent run " + std::to_string(i + 1) + ": " + errors[i]);
    require(concurrent[i] == sequential[i],
            "instance " + std::to_string(i + 1) + " run concurrently differs from its run alone");
  }
  return {true, ""};
}

}  // namespace

std::vector<Check> robustness_checks(const clothlab_integrator& integrator) {
  const clothlab_integrator* c = &integrator;
  return {
      {c->id, "robustness.no-throw", [c] { return on_every_shape(*c, nothing_escapes); }},
      {c->id, "robustness.no-alloc", [c] { return on_every_shape(*c, step_does_not_allocate); }},
      {c->id, "robustness.concurrent",
       [c] { return on_every_shape(*c, concurrent_equals_sequential); }},
  };
}

}  // namespace clothlab::conformance
