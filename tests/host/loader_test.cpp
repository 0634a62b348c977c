#include <gtest/gtest.h>

#include <clothlab/host/errors.hpp>
#include <clothlab/host/library_handle.hpp>
#include <clothlab/host/plugin_library.hpp>
#include <optional>
#include <string>

#include "plugins/test_point_echo.h"
#include "test_paths.hpp"

namespace clothlab::host {
namespace {

using test::test_plugin_dir;

// The message of the PluginLoadError that loading `path` throws, or "" if none.
std::string load_error(const std::filesystem::path& path) {
  try {
    PluginLibrary::load(path);
  } catch (const PluginLoadError& error) {
    return error.what();
  }
  return "";
}

const std::filesystem::path good = test_plugin_dir("good") / "clothlab_test_good.so";

TEST(PluginLibrary, LoadsAGoodPluginAndDescribesItsComponents) {
  const PluginLibrary library = PluginLibrary::load(good);
  EXPECT_EQ(library.name(), "clothlab-test-good");
  EXPECT_EQ(library.version(), "0.1.0");
  EXPECT_EQ(library.abi_version().major, CLOTHLAB_ABI_VERSION_MAJOR);
  ASSERT_EQ(library.integrators().size(), 1u);
  ASSERT_EQ(library.scenarios().size(), 1u);
  const IntegratorPlugin& integrator = library.integrator();
  EXPECT_EQ(integrator.info().id, "test-drift");
  EXPECT_EQ(integrator.info().kind, "integrator");
  EXPECT_EQ(integrator.order(), 1u);
  EXPECT_FALSE(integrator.uses_velocity_forces());
  EXPECT_TRUE(integrator.supports_precision(CLOTHLAB_FLOAT32));
  EXPECT_TRUE(integrator.supports_precision(CLOTHLAB_FLOAT64));
  EXPECT_EQ(integrator.info().params.size(), 4u);
  EXPECT_EQ(library.scenario().info().id, "test-point");
}

TEST(PluginLibrary, ParametersResolveFromDefaultsAndSettings) {
  const PluginLibrary library = PluginLibrary::load(good);
  ParamSet params = library.integrator().default_params();
  EXPECT_EQ(params.value("gain").v[0], 1.0);
  EXPECT_EQ(params.value("count").v[0], 3.0);
  EXPECT_EQ(params.value("enabled").v[0], 1.0);
  EXPECT_EQ(params.value("offset").v[2], 3.0);
  params.set("gain", "2.5", "--set");
  params.set("offset", "[0, -1, 4]", "--set");
  EXPECT_EQ(params.value("gain").v[0], 2.5);
  EXPECT_EQ(params.value("offset").v[1], -1.0);
  EXPECT_NO_THROW(library.integrator().create(params));
}

TEST(PluginLibrary, ScenarioDescribesTheSceneItsParametersAsk) {
  const PluginLibrary library = PluginLibrary::load(good);
  ParamSet params = library.scenario().default_params();
  params.set("rows", "5", "--set");
  const clothlab_scene scene = library.scenario().create(params).describe();
  EXPECT_EQ(scene.rows, 5u);
  EXPECT_EQ(scene.cols, 1u);
}

TEST(PluginLibrary, InstancesKeepTheLibraryLoadedAfterTheLibraryObjectIsGone) {
  ASSERT_FALSE(LibraryHandle::is_loaded(good));
  std::optional<ScenarioInstance> instance;
  {
    const PluginLibrary library = PluginLibrary::load(good);
    ASSERT_TRUE(LibraryHandle::is_loaded(good));
    instance.emplace(library.scenario().create(library.scenario().default_params()));
  }
  EXPECT_TRUE(LibraryHandle::is_loaded(good));
  EXPECT_EQ(instance->describe().rows, 2u);
  instance.reset();
  EXPECT_FALSE(LibraryHandle::is_loaded(good));
}

TEST(PluginLibrary, MissingFileIsAnErrorNamingIt) {
  const auto path = test_plugin_dir("good") / "no_such_plugin.so";
  const std::string message = load_error(path);
  EXPECT_NE(message.find(path.string()), std::string::npos) << message;
  EXPECT_NE(message.find("no such file"), std::string::npos) << message;
}

TEST(PluginLibrary, TextFileIsNotASharedLibrary) {
  const auto path = test_plugin_dir("bad") / "clothlab_test_not_a_library.so";
  const std::string message = load_error(path);
  EXPECT_NE(message.find(path.string()), std::string::npos) << message;
  EXPECT_NE(message.find("not a loadable shared library"), std::string::npos) << message;
  // dlopen's own reason follows.
  EXPECT_NE(message.find("ELF"), std::string::npos) << message;
}

TEST(PluginLibrary, LibraryWithoutEntrySymbolIsRefused) {
  const auto path = test_plugin_dir("bad") / "clothlab_test_no_entry.so";
  const std::string message = load_error(path);
  EXPECT_NE(message.find(path.string()), std::string::npos) << message;
  EXPECT_NE(message.find("no entry symbol clothlab_plugin_entry"), std::string::npos) << message;
}

TEST(PluginLibrary, OtherAbiMajorIsRefusedNamingBothVersions) {
  const auto path = test_plugin_dir("bad") / "clothlab_test_abi999.so";
  const std::string message = load_error(path);
  EXPECT_NE(message.find(path.string()), std::string::npos) << message;
  EXPECT_NE(message.find("library: abi_version = 999.0, allowed 1.x"), std::string::npos)
      << message;
  EXPECT_NE(message.find("host ABI version 1."), std::string::npos) << message;
}

TEST(PluginLibrary, ALaterMinorVersionWithAppendedFieldsIsAccepted) {
  const PluginLibrary library =
      PluginLibrary::load(test_plugin_dir("minor") / "clothlab_test_future_minor.so");
  EXPECT_EQ(library.abi_version().minor, 99u);
  EXPECT_EQ(library.name(), "clothlab-test-future-minor");
}

TEST(PluginLibrary, AScenarioFromAbi12LoadsWithoutExtensionsAndNeverHasItsTailRead) {
  const PluginLibrary library =
      PluginLibrary::load(test_plugin_dir("minor") / "clothlab_test_legacy_scenario.so");
  const ScenarioPlugin& scenario = library.scenario();
  EXPECT_EQ(scenario.descriptor().struct_size, CLOTHLAB_SCENARIO_SIZE_1_0);
  EXPECT_EQ(scenario.extension("clothlab.colliders/1"), nullptr);
  const clothlab_scene scene = scenario.create(scenario.default_params()).describe();
  EXPECT_EQ(scene.cols, 2u);
  EXPECT_EQ(scene.pinned_count, 1u);
}

// clothlab.text-parameters/1 with a null default text: refused before anything reads it.
TEST(PluginLibrary, AMalformedTextParameterSpecIsRefusedNamingTheComponent) {
  const PluginLibrary library =
      PluginLibrary::load(test_plugin_dir("malformed_text") / "clothlab_test_malformed_text.so");
  try {
    (void)library.scenario().default_params();
    FAIL() << "a spec with a null default text was accepted";
  } catch (const PluginError& error) {
    EXPECT_STREQ(error.what(),
                 "scenario test-malformed-text: clothlab.text-parameters/1 spec 0 is malformed (a "
                 "null name, help or default, or no length)");
  }
}

TEST(PluginLibrary, SdkScenariosOfferTheirExtensionsThroughTheLoader) {
  const PluginLibrary library = PluginLibrary::load(good);
  const ScenarioPlugin& scenario = library.scenario();
  EXPECT_EQ(scenario.descriptor().struct_size, sizeof(clothlab_scenario));
  const auto* echo =
      static_cast<const clothlab_test_point_echo*>(scenario.extension(CLOTHLAB_TEST_POINT_ECHO));
  ASSERT_NE(echo, nullptr);
  ParamSet params = scenario.default_params();
  params.set("rows", "5", "test");
  const ScenarioInstance instance = scenario.create(params);
  EXPECT_EQ(echo->rows(instance.get()), 5u);
  EXPECT_EQ(scenario.extension("clothlab.test-point-echo/2"), nullptr);
  EXPECT_EQ(scenario.extension(nullptr), nullptr);
}

TEST(PluginLibrary, DescriptorShorterThanTheHostReadsIsRefused) {
  const std::string message =
      load_error(test_plugin_dir("bad") / "clothlab_test_short_descriptor.so");
  EXPECT_NE(message.find("library: struct_size = 16, allowed at least"), std::string::npos)
      << message;
}

TEST(PluginLibrary, DuplicateIdsWithinALibraryAreRefused) {
  const auto path = test_plugin_dir("bad") / "clothlab_test_duplicate_ids.so";
  const std::string message = load_error(path);
  EXPECT_NE(message.find(path.string()), std::string::npos) << message;
  EXPECT_NE(message.find("integrator twin: id = \"twin\", allowed an id no other component"),
            std::string::npos)
      << message;
}

// Of the two faults descriptor_findings reports, the loader's one-line refusal names the first:
// the file, the field, the value and what is allowed.
TEST(PluginLibrary, RefusesOnTheFirstFindingNamingFieldValueAndRange) {
  const auto path = test_plugin_dir("two_faults") / "clothlab_test_two_param_faults.so";
  EXPECT_EQ(load_error(path), "cannot load plugin " + path.string() +
                                  ": integrator misdeclares-two-params: "
                                  "params.substeps.default_value = 2.5, allowed int in [1, 64]");
}

TEST(PluginLibrary, FindAddsTheSearchPathToLoadErrors) {
  const PluginSearchPath search_path({test_plugin_dir("bad")});
  try {
    PluginLibrary::find("clothlab_test_no_entry", search_path);
    FAIL() << "loaded a library without entry symbol";
  } catch (const PluginLoadError& error) {
    EXPECT_NE(std::string(error.what()).find(search_path.describe()), std::string::npos)
        << error.what();
  }
}

TEST(ScanLibraries, ReportsIdsProvidedByTwoLibraries) {
  const LibraryScan scan =
      scan_libraries(PluginSearchPath({test_plugin_dir("good"), test_plugin_dir("copy")}));
  EXPECT_EQ(scan.libraries.size(), 2u);
  ASSERT_EQ(scan.errors.size(), 2u);  // the integrator and the scenario
  EXPECT_NE(scan.errors[0].find("duplicate plugin id test-drift"), std::string::npos)
      << scan.errors[0];
  EXPECT_NE(scan.errors[0].find("clothlab_test_good_copy.so"), std::string::npos);
}

TEST(ScanLibraries, ReportsEachBadLibraryAndKeepsGoing) {
  const LibraryScan scan =
      scan_libraries(PluginSearchPath({test_plugin_dir("bad"), test_plugin_dir("good")}));
  EXPECT_EQ(scan.libraries.size(), 1u);
  EXPECT_EQ(scan.errors.size(), 5u);  // every library in bad/
}

}  // namespace
}  // namespace clothlab::host
