// XPBD on the engine's flag (wind): the external phase inside its wavefront
// (clothlab.external-forces/2's ranges) gives the host pass's bits, and a step's substeps in one
// parallel region, the seam of one overlapping the next, give the same bits on any thread
// count.
#include <clothlab/ext/external_forces.h>
#include <gtest/gtest.h>

#include <clothlab/core/cloth.hpp>
#include <clothlab/host/param_set.hpp>
#include <clothlab/host/plugin_library.hpp>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

namespace clothlab {
namespace {

const std::filesystem::path plugins = CLOTHLAB_BUILTIN_PLUGIN_DIR;

// 110 x 120: enough springs for xpbd to use several threads, two bands.
Scene flag_scene() {
  const host::PluginLibrary library = host::PluginLibrary::load(plugins / "flag.so");
  host::ParamSet values = library.scenario().default_params();
  values.set("rows", "110", "test");
  values.set("cols", "120", "test");
  return scene_from_abi(library.scenario().create(values).describe());
}

// The engine's system, its get_extension hiding external-forces/2: xpbd then runs the host's
// external pass before each substep.
const clothlab_system* hidden_from = nullptr;
const void* without_ranges(void* context, const char* id) {
  if (id != nullptr && std::strcmp(id, CLOTHLAB_EXT_EXTERNAL_FORCES_2) == 0) return nullptr;
  return hidden_from->get_extension(context, id);
}

std::vector<float> after_steps(int threads, bool ranges) {
  Cloth cloth(flag_scene(), Precision::Float32, {true, threads});
  clothlab_system system = cloth.system();
  hidden_from = &cloth.system();
  if (!ranges) system.get_extension = &without_ranges;
  const host::PluginLibrary library = host::PluginLibrary::load(plugins / "xpbd.so");
  host::ParamSet values = library.integrator().default_params();
  values.set("substeps", "6", "test");
  values.set("threads", std::to_string(threads), "test");
  host::IntegratorInstance xpbd = library.integrator().create(values);
  xpbd.prepare(system);
  for (int step = 0; step < 4; ++step) xpbd.step(system, step * 1e-2, 1e-2);
  std::vector<float> x, v;
  cloth.positions(x);
  cloth.velocities(v);
  x.insert(x.end(), v.begin(), v.end());
  return x;
}

TEST(XpbdEngine, ExternalPhaseInTheSweepIsTheHostPassBitForBit) {
  EXPECT_EQ(after_steps(1, true), after_steps(1, false));
  EXPECT_EQ(after_steps(2, true), after_steps(2, false));
}

TEST(XpbdEngine, SameBitsOnAnyThreadCount) {
  const std::vector<float> one = after_steps(1, true);
  EXPECT_EQ(after_steps(2, true), one);
  EXPECT_EQ(after_steps(3, true), one);
}

}  // namespace
}  // namespace clothlab
