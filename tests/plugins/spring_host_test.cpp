// The plugin tests' spring host (spring_host.hpp) against the extension registry: every host
// extension answered, once its grid and thread count are set, or declined by name.
#include "spring_host.hpp"

#include <gtest/gtest.h>

#include <clothlab/core/extension_registry.hpp>

namespace clothlab::test {
namespace {

TEST(SpringHost, AnswersOrDeclinesEveryHostExtension) {
  SpringHost<double> host(9, {0}, provot_net_springs(3, 3, 0.1, 100, 10, 0.1), {0, -9.81, 0});
  host.set_grid(3, 3, 0.1, {});
  host.set_threads(1);
  const clothlab_system& system = host.system().raw();
  EXPECT_EQ(extension_coverage(
                "the spring host", ExtensionSide::Host,
                [&](const char* id) { return system.get_extension(system.context, id); },
                SpringHost<double>::kDeclinedExtensions),
            "");
}

}  // namespace
}  // namespace clothlab::test
