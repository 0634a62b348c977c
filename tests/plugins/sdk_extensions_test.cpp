// The SDK's extension glue: System<Real>::extension finds host tables only on a 1.2 host,
// the typed accessors throw UNSUPPORTED naming the missing id, an integrator's
// get_extension returns exactly the tables its class declares, scenario glue accepts
// a 1.0-sized scene buffer, and a scenario's get_extension (ABI 1.3) returns its class's tables.
#include <gtest/gtest.h>

#include <clothlab/sdk.hpp>
#include <clothlab/sdk/threads.hpp>
#include <cstring>
#include <string>
#include <string_view>

namespace clothlab::test {
namespace {

// A host that offers only the reductions extension, with a dot that counts its calls.
struct ReductionsOnlyHost {
  int dots = 0;
  static double dot(void* context, const void*, const void*) {
    ++static_cast<ReductionsOnlyHost*>(context)->dots;
    return 42.0;
  }
  static double mass_dot(void*, const void*, const void*) { return 0.0; }
  static double max_abs(void*, const void*) { return 0.0; }
  static constexpr clothlab_reductions_extension reductions{&dot, &mass_dot, &max_abs};
  static const void* get_extension(void*, const char* id) {
    return id != nullptr && std::strcmp(id, CLOTHLAB_EXT_REDUCTIONS) == 0 ? &reductions : nullptr;
  }
  clothlab_system system() {
    clothlab_system raw{};
    raw.struct_size = sizeof raw;
    raw.precision = CLOTHLAB_FLOAT64;
    raw.context = this;
    raw.get_extension = &get_extension;
    return raw;
  }
};

TEST(SdkSystemExtensions, FindsAnOfferedTableAndCallsIt) {
  ReductionsOnlyHost host;
  const clothlab_system raw = host.system();
  const sdk::System<double> system(raw);
  ASSERT_EQ(system.extension<clothlab_reductions_extension>(CLOTHLAB_EXT_REDUCTIONS),
            &ReductionsOnlyHost::reductions);
  EXPECT_EQ(system.reductions().dot(nullptr, nullptr), 42.0);
  EXPECT_EQ(host.dots, 1);
}

TEST(SdkSystemExtensions, AbsentExtensionIsNullAndItsAccessorThrowsUnsupported) {
  ReductionsOnlyHost host;
  const clothlab_system raw = host.system();
  const sdk::System<double> system(raw);
  EXPECT_EQ(system.extension<clothlab_jacobian_extension>(CLOTHLAB_EXT_JACOBIAN), nullptr);
  EXPECT_EQ(system.extension<clothlab_jacobian_extension>("clothlab.reductions/2"), nullptr);
  try {
    (void)system.jacobian();
    FAIL() << "jacobian() on a host without it did not throw";
  } catch (const sdk::Error& e) {
    EXPECT_EQ(e.status(), CLOTHLAB_ERROR_UNSUPPORTED);
    EXPECT_EQ(std::string(e.what()), "the host lacks clothlab.jacobian/1");
  }
}

// The grid is what a host may say, not what it must offer: no grid is an empty optional.
TEST(SdkSystemExtensions, WithoutTheGridExtensionTheClothIsNoGrid) {
  ReductionsOnlyHost host;
  const clothlab_system raw = host.system();
  const sdk::System<double> system(raw);
  EXPECT_FALSE(system.grid().has_value());
}

// A host that offers only the thread count (clothlab.threads/1), 3.
struct ThreeThreadsHost {
  static uint32_t count(void*) { return 3; }
  static constexpr clothlab_threads_extension threads{&count};
  static const void* get_extension(void*, const char* id) {
    return id != nullptr && std::strcmp(id, CLOTHLAB_EXT_THREADS) == 0 ? &threads : nullptr;
  }
};

// The thread count, likewise: nothing from a host that does not offer clothlab.threads/1.
TEST(SdkSystemExtensions, ThreadsAreTheHostsCountOrNothing) {
  ReductionsOnlyHost without;
  const clothlab_system raw_without = without.system();
  EXPECT_FALSE(sdk::System<double>(raw_without).threads().has_value());
  clothlab_system raw = raw_without;
  raw.get_extension = &ThreeThreadsHost::get_extension;
  EXPECT_EQ(sdk::System<double>(raw).threads(), std::optional<uint32_t>(3));
}

// A plugin's thread count (sdk/threads.hpp): its parameter when set, else the host's count,
// else the runtime's default; one thread for work too small to split.
TEST(SdkPluginThreads, TheParameterThenTheHostThenTheRuntime) {
  EXPECT_EQ(sdk::resolve_threads(2, 3u, 8, true), 2);
  EXPECT_EQ(sdk::resolve_threads(0, 3u, 8, true), 3);
  EXPECT_EQ(sdk::resolve_threads(0, std::nullopt, 8, true), 8);
  EXPECT_EQ(sdk::resolve_threads(4, 3u, 8, false), 1);
  EXPECT_EQ(sdk::resolve_threads(0, 0u, 8, true), 1);  // a host's 0 is still one thread

  ReductionsOnlyHost without;
  clothlab_system raw = without.system();
  raw.get_extension = &ThreeThreadsHost::get_extension;
  const sdk::System<double> system(raw);
  EXPECT_EQ(sdk::plugin_threads(system, 0, true), 3);
  EXPECT_EQ(sdk::plugin_threads(system, 2, true), 2);
  EXPECT_EQ(sdk::plugin_threads(system, 0, false), 1);
}

TEST(SdkSystemExtensions, AHostOlderThan1_2IsNeverAskedEvenIfTheBytesLookLikeAPointer) {
  for (const size_t size : {size_t{CLOTHLAB_SYSTEM_SIZE_1_0}, size_t{CLOTHLAB_SYSTEM_SIZE_1_1}}) {
    ReductionsOnlyHost host;
    clothlab_system raw = host.system();
    raw.struct_size = static_cast<uint32_t>(size);  // get_extension lies beyond the struct
    const sdk::System<double> system(raw);
    EXPECT_EQ(system.extension<clothlab_reductions_extension>(CLOTHLAB_EXT_REDUCTIONS), nullptr);
    EXPECT_THROW((void)system.reductions(), sdk::Error);
  }
}

struct Plain {
  static constexpr const char* id = "plain";
  static constexpr const char* name = "Plain";
  static constexpr const char* version = "1.0.0";
  static constexpr const char* description = "declares no extension";
  static constexpr uint32_t order = 1, evals_per_step = 1, flags = 0;
  static constexpr std::array<clothlab_param_spec, 0> params{};
  explicit Plain(const sdk::Params&) {}
  template <class Real>
  void prepare(sdk::System<Real>&) {}
  template <class Real>
  void step(sdk::System<Real>&, double, double) {}
};

struct Declaring : Plain {
  using Plain::Plain;
  static constexpr sdk::RknScheme<1> scheme{{0.0}, {0.0}, {0.0}, {0.0}, {1.0}, {1.0}};
  static constexpr clothlab_rkn_scheme raw_scheme = scheme.raw();
  static constexpr clothlab_explicit_scheme explicit_scheme = sdk::explicit_scheme_of(raw_scheme);
  static constexpr clothlab_integrator_traits traits{sizeof(clothlab_integrator_traits),
                                                     CLOTHLAB_TRAIT_UNCONDITIONALLY_STABLE, nullptr,
                                                     "iterations"};
};

TEST(SdkIntegratorExtensions, DescriptorIs1_2SizedAndReturnsOnlyDeclaredTables) {
  const clothlab_integrator& plain = *sdk::integrator_descriptor<Plain>();
  const clothlab_integrator& declaring = *sdk::integrator_descriptor<Declaring>();
  for (const clothlab_integrator* descriptor : {&plain, &declaring}) {
    EXPECT_EQ(descriptor->struct_size, CLOTHLAB_INTEGRATOR_SIZE_1_2);
    ASSERT_TRUE(CLOTHLAB_HAS_FIELD(descriptor, clothlab_integrator, get_extension));
    ASSERT_NE(descriptor->get_extension, nullptr);
    EXPECT_EQ(descriptor->get_extension(nullptr), nullptr);
    EXPECT_EQ(descriptor->get_extension("clothlab.no-such-extension/1"), nullptr);
  }
  EXPECT_EQ(plain.get_extension(CLOTHLAB_EXT_INTEGRATOR_TRAITS), nullptr);
  EXPECT_EQ(plain.get_extension(CLOTHLAB_EXT_EXPLICIT_SCHEME), nullptr);

  const auto* traits = static_cast<const clothlab_integrator_traits*>(
      declaring.get_extension(CLOTHLAB_EXT_INTEGRATOR_TRAITS));
  ASSERT_NE(traits, nullptr);
  EXPECT_EQ(traits->flags, CLOTHLAB_TRAIT_UNCONDITIONALLY_STABLE);
  EXPECT_STREQ(traits->iterations_param, "iterations");
  const auto* scheme = static_cast<const clothlab_explicit_scheme*>(
      declaring.get_extension(CLOTHLAB_EXT_EXPLICIT_SCHEME));
  ASSERT_NE(scheme, nullptr);
  EXPECT_EQ(scheme->first_same_as_last, 0u);
  EXPECT_EQ(scheme->scheme->stages, 1u);
  EXPECT_EQ(scheme->scheme->v_weights[0], 1.0);
  EXPECT_EQ(declaring.get_extension("clothlab.explicit-scheme/2"), nullptr);
}

struct TinyScenario {
  static constexpr const char* id = "tiny";
  static constexpr const char* name = "Tiny";
  static constexpr const char* version = "1.0.0";
  static constexpr const char* description = "a 1x1 cloth";
  static constexpr std::array<clothlab_param_spec, 0> params{};
  explicit TinyScenario(const sdk::Params&) {}
  void describe(clothlab_scene& scene) const {
    scene.rows = 1;
    scene.cols = 1;
  }
};

TEST(SdkScenarioGlue, AcceptsA1_0SceneBufferAndRefusesASmallerOne) {
  const clothlab_scenario& scenario = *sdk::scenario_descriptor<TinyScenario>();
  void* instance = nullptr;
  clothlab_message message{};
  ASSERT_EQ(scenario.create(nullptr, 0, &instance, &message), CLOTHLAB_OK) << message.text;
  clothlab_scene scene{};
  scene.struct_size = CLOTHLAB_SCENE_SIZE_1_0;
  EXPECT_EQ(scenario.describe(instance, &scene, &message), CLOTHLAB_OK) << message.text;
  EXPECT_EQ(scene.rows, 1u);
  scene.struct_size = CLOTHLAB_SCENE_SIZE_1_0 - 8;
  EXPECT_EQ(scenario.describe(instance, &scene, &message), CLOTHLAB_ERROR_INVALID_ARGUMENT);
  EXPECT_STREQ(message.text, "scene buffer too small");
  scenario.destroy(instance);
}

// A scenario offering one table of its own, whose function reads the instance.
struct ScenarioWithTable : TinyScenario {
  using TinyScenario::TinyScenario;
  struct Table {
    int (*answer)(void* instance);
  };
  int answer = 42;
  static const void* extension(std::string_view id) noexcept {
    static constexpr Table table{
        [](void* instance) { return static_cast<ScenarioWithTable*>(instance)->answer; }};
    return id == "test.answer/1" ? &table : nullptr;
  }
};

TEST(SdkScenarioExtensions, DescriptorIs1_3SizedAndReturnsOnlyTheClassTables) {
  const clothlab_scenario& plain = *sdk::scenario_descriptor<TinyScenario>();
  EXPECT_EQ(plain.struct_size, CLOTHLAB_SCENARIO_SIZE_1_3);
  EXPECT_EQ(clothlab_scenario_extension(&plain, "test.answer/1"), nullptr);

  const clothlab_scenario& offering = *sdk::scenario_descriptor<ScenarioWithTable>();
  EXPECT_EQ(clothlab_scenario_extension(&offering, "test.answer/2"), nullptr);
  EXPECT_EQ(clothlab_scenario_extension(&offering, nullptr), nullptr);
  const auto* table = static_cast<const ScenarioWithTable::Table*>(
      clothlab_scenario_extension(&offering, "test.answer/1"));
  ASSERT_NE(table, nullptr);
  void* instance = nullptr;
  clothlab_message message{};
  ASSERT_EQ(offering.create(nullptr, 0, &instance, &message), CLOTHLAB_OK) << message.text;
  EXPECT_EQ(table->answer(instance), 42);
  offering.destroy(instance);
}

TEST(SdkScenarioExtensions, AScenarioOlderThan1_3IsNeverAskedEvenIfTheBytesLookLikeAPointer) {
  clothlab_scenario legacy = *sdk::scenario_descriptor<ScenarioWithTable>();
  legacy.struct_size = CLOTHLAB_SCENARIO_SIZE_1_0;
  EXPECT_EQ(clothlab_scenario_extension(&legacy, "test.answer/1"), nullptr);
}

}  // namespace
}  // namespace clothlab::test
