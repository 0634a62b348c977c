// Binaries built with ABI 1.0- and 1.1-sized structs (abi_minor/legacy_euler.c) load through
// the host's loader, offer no extension (the loader never reads past struct_size: the
// field there aborts when called) and step the cloth exactly as the built-in symplectic
// Euler does: through the 1.1 fused step bit for bit, through the 1.0 callbacks to rounding.
#include <clothlab/ext/explicit_scheme.h>
#include <gtest/gtest.h>

#include <clothlab/host/plugin_library.hpp>
#include <cmath>
#include <string>

#include "fixtures.hpp"

namespace clothlab::conformance {
namespace {

std::string subject(const std::string& name) {
  return std::string(CONFORMANCE_PLUGIN_DIR) + "/" + name + ".so";
}

State run(const host::PluginLibrary& library, Precision precision) {
  return simulate(library.integrator().descriptor(), sheet_scene(12, 9, true), precision, 1, 200,
                  1e-3);
}

TEST(LegacyAbi, OldMinorsLoadWithoutExtensionsAndNeverHaveTheirTailRead) {
  for (const char* name : {"abi_legacy_1_0", "abi_legacy_1_1"}) {
    const host::PluginLibrary library = host::PluginLibrary::load(subject(name));
    EXPECT_EQ(library.abi_version().major, 1u);
    const host::IntegratorPlugin& integrator = library.integrator();
    EXPECT_EQ(integrator.descriptor().struct_size, CLOTHLAB_INTEGRATOR_SIZE_1_0);
    EXPECT_EQ(integrator.extension(CLOTHLAB_EXT_EXPLICIT_SCHEME), nullptr) << name;
  }
}

TEST(LegacyAbi, OldMinorsGiveTheResultsOfTheBuiltInSymplecticEuler) {
  const host::PluginLibrary builtin =
      host::PluginLibrary::load(std::string(BUILTIN_PLUGIN_DIR) + "/euler.so");
  const host::PluginLibrary minor_0 = host::PluginLibrary::load(subject("abi_legacy_1_0"));
  const host::PluginLibrary minor_1 = host::PluginLibrary::load(subject("abi_legacy_1_1"));
  for (const Precision precision : {Precision::Float64, Precision::Float32}) {
    const State expected = run(builtin, precision);
    EXPECT_TRUE(run(minor_1, precision) == expected) << to_string(precision);
    const State unfused = run(minor_0, precision);
    double worst = 0;
    for (std::size_t e = 0; e < expected.x.size(); ++e)
      worst = std::max(worst, std::abs(unfused.x[e] - expected.x[e]));
    EXPECT_LT(worst, precision == Precision::Float64 ? 1e-12 : 1e-4) << to_string(precision);
  }
}

}  // namespace
}  // namespace clothlab::conformance
