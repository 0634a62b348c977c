// The no-allocation check's interposer (host/conformance/plugin_only_system.hpp) passes on every
// host extension of the registry the engine offers, contacts and attachment targets included,
// each calling the engine with the engine's own context.
#include "plugin_only_system.hpp"

#include <gtest/gtest.h>

#include <clothlab/core/extension_registry.hpp>

#include "fixtures.hpp"

namespace clothlab::conformance {
namespace {

TEST(PluginOnlySystem, AnswersOrDeclinesEveryHostExtension) {
  const Cloth cloth(sheet_scene(4, 4), Precision::Float64, PipelineOptions{true, 1});
  const PluginOnlySystem wrapper(cloth.system());
  const clothlab_system& system = wrapper.system();
  EXPECT_EQ(extension_coverage(
                "the interposer", ExtensionSide::Host,
                [&](const char* id) { return system.get_extension(system.context, id); },
                PluginOnlySystem::kDeclinedExtensions),
            "");
}

TEST(PluginOnlySystem, ForwardsContactsAndAttachmentTargetsToTheHost) {
  const Cloth cloth(sheet_scene(4, 4), Precision::Float64, PipelineOptions{true, 1});
  const PluginOnlySystem wrapper(cloth.system());
  const clothlab_system& system = wrapper.system();
  const auto* contacts = static_cast<const clothlab_contacts_extension*>(
      system.get_extension(system.context, CLOTHLAB_EXT_CONTACTS));
  const auto* targets = static_cast<const clothlab_attachment_targets_extension*>(
      system.get_extension(system.context, CLOTHLAB_EXT_ATTACHMENT_TARGETS));
  ASSERT_NE(contacts, nullptr);
  ASSERT_NE(targets, nullptr);
  EXPECT_EQ(contacts->resolve(system.context, 0.0, system.x, system.v), CLOTHLAB_OK);
  EXPECT_EQ(targets->count(system.context), 0u);
  EXPECT_EQ(targets->move(system.context, 0.0, system.x, system.v), CLOTHLAB_OK);
  EXPECT_TRUE(wrapper.misuse().empty()) << wrapper.misuse();
}

}  // namespace
}  // namespace clothlab::conformance
