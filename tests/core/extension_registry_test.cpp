// The extension registry (clothlab/core/extension_registry.hpp) and the tables that answer its
// host-side ids here: the engine, which answers every one, and the reference system, which
// declines the ones it names. The coverage check is also run on faulty lookups it must catch.
#include <gtest/gtest.h>

#include <algorithm>
#include <clothlab/core/extension_registry.hpp>
#include <set>
#include <string>

#include "cloth_test_support.hpp"
#include "reference_system.hpp"

namespace clothlab {
namespace {

std::function<const void*(const char*)> lookup_of(const clothlab_system& system) {
  return [&system](const char* id) { return system.get_extension(system.context, id); };
}

TEST(ExtensionRegistry, IdsAreUniqueNamesWithARevision) {
  std::set<std::string> seen;
  for (const PublishedExtension& extension : kPublishedExtensions) {
    const std::string id = extension.id;
    EXPECT_TRUE(seen.insert(id).second) << id << " is listed twice";
    EXPECT_EQ(id.rfind("clothlab.", 0), 0u) << id;
    const std::size_t slash = id.rfind('/');
    ASSERT_NE(slash, std::string::npos) << id;
    EXPECT_GE(std::stoi(id.substr(slash + 1)), 1) << id;
  }
}

TEST(ExtensionRegistry, APluginIdBelongsToBothPluginSidesAndNotTheHost) {
  const auto has = [](ExtensionSide side, std::string_view id) {
    const std::vector<const char*> ids = published_ids(side);
    return std::any_of(ids.begin(), ids.end(), [id](const char* p) { return id == p; });
  };
  EXPECT_TRUE(has(ExtensionSide::Integrator, CLOTHLAB_EXT_TEXT_PARAMETERS));
  EXPECT_TRUE(has(ExtensionSide::Scenario, CLOTHLAB_EXT_TEXT_PARAMETERS));
  EXPECT_FALSE(has(ExtensionSide::Host, CLOTHLAB_EXT_TEXT_PARAMETERS));
  EXPECT_FALSE(has(ExtensionSide::Integrator, CLOTHLAB_EXT_MESH));
}

TEST(ExtensionRegistry, UnpublishedIdsAreNotPublished) {
  for (ExtensionSide side :
       {ExtensionSide::Host, ExtensionSide::Integrator, ExtensionSide::Scenario}) {
    const std::vector<std::string> ids = unpublished_ids(side);
    EXPECT_GT(ids.size(), 2 * published_ids(side).size()) << to_string(side);
    for (const std::string& id : ids) EXPECT_FALSE(is_published(id)) << id;
    for (const std::string& id : ids) EXPECT_EQ(std::count(ids.begin(), ids.end(), id), 1) << id;
  }
  // Two published revisions of one name: the ones around both, not the one between.
  const std::vector<std::string> scenario = unpublished_ids(ExtensionSide::Scenario);
  for (const char* id : {"clothlab.colliders/0", "clothlab.colliders/3", "clothlab.colliders"})
    EXPECT_NE(std::find(scenario.begin(), scenario.end(), id), scenario.end()) << id;
  EXPECT_EQ(std::find(scenario.begin(), scenario.end(), "clothlab.colliders/2"), scenario.end());
}

TEST(ExtensionRegistry, EngineAnswersEveryHostExtension) {
  for (Precision precision : {Precision::Float32, Precision::Float64}) {
    const Cloth cloth(testing::bare_scene(4, 5), precision, {});
    EXPECT_EQ(extension_coverage("the engine", ExtensionSide::Host, lookup_of(cloth.system()), {}),
              "");
  }
}

TEST(ExtensionRegistry, ReferenceSystemAnswersOrDeclinesEveryHostExtension) {
  const reference::ReferenceSystem<double> reference(testing::bare_scene(4, 5), true);
  EXPECT_EQ(
      extension_coverage("the reference system", ExtensionSide::Host, lookup_of(reference.system()),
                         reference::ReferenceSystem<double>::kDeclinedExtensions),
      "");
}

// The faults the check exists for: an id neither answered nor declined, an id both, a declined
// id nobody publishes, an answer to a revision nobody publishes.
TEST(ExtensionRegistry, CoverageCatchesEachFault) {
  const Cloth cloth(testing::bare_scene(4, 5), Precision::Float64, {});
  const auto engine = lookup_of(cloth.system());
  const auto lacks_contacts = [&](const char* id) -> const void* {
    return std::string(id) == CLOTHLAB_EXT_CONTACTS ? nullptr : engine(id);
  };
  EXPECT_NE(extension_coverage("t", ExtensionSide::Host, lacks_contacts, {})
                .find("neither answers nor declines " CLOTHLAB_EXT_CONTACTS),
            std::string::npos);
  const char* const contacts[] = {CLOTHLAB_EXT_CONTACTS};
  EXPECT_EQ(extension_coverage("t", ExtensionSide::Host, lacks_contacts, contacts), "");
  EXPECT_NE(extension_coverage("t", ExtensionSide::Host, engine, contacts)
                .find("answers " CLOTHLAB_EXT_CONTACTS ", which it declines"),
            std::string::npos);
  const char* const unknown[] = {"clothlab.contacts/7"};
  EXPECT_NE(extension_coverage("t", ExtensionSide::Host, engine, unknown).find("not published"),
            std::string::npos);
  const auto any_revision = [&](const char* id) -> const void* {
    return std::string(id) == "clothlab.grid/2" ? engine(CLOTHLAB_EXT_GRID) : engine(id);
  };
  EXPECT_NE(extension_coverage("t", ExtensionSide::Host, any_revision, {})
                .find("answers \"clothlab.grid/2\""),
            std::string::npos);
}

}  // namespace
}  // namespace clothlab
