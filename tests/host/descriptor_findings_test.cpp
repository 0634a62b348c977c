// The one descriptor validator: every finding, each naming its component, field, value and what
// is allowed; the rules the loader once lacked (a bool's range, a whole-number default, a
// library without components) hold for it too.
#include <gtest/gtest.h>

#include <array>
#include <clothlab/host/descriptor_findings.hpp>
#include <clothlab/host/plugin_library.hpp>
#include <string>
#include <vector>

namespace clothlab::host {
namespace {

clothlab_status create(const clothlab_param_value*, uint32_t, void**, clothlab_message*) {
  return CLOTHLAB_ERROR_UNSUPPORTED;
}
clothlab_status prepare(void*, const clothlab_system*, clothlab_message*) {
  return CLOTHLAB_ERROR_UNSUPPORTED;
}
clothlab_status step(void*, const clothlab_system*, double, double, clothlab_message*) {
  return CLOTHLAB_ERROR_UNSUPPORTED;
}
void destroy(void*) {}

clothlab_param_spec int_spec(const char* name, double fallback, double low, double high) {
  return {sizeof(clothlab_param_spec),
          CLOTHLAB_PARAM_INT,
          name,
          "help",
          "",
          {fallback, 0, 0},
          low,
          high};
}

clothlab_param_spec bool_spec(const char* name, double low, double high) {
  return {sizeof(clothlab_param_spec), CLOTHLAB_PARAM_BOOL, name, "help", "", {0, 0, 0}, low, high};
}

// A library of one integrator with the given parameters, sound in every other field.
struct OneIntegrator {
  explicit OneIntegrator(std::vector<clothlab_param_spec> specs) : params(std::move(specs)) {
    integrator.struct_size = sizeof(clothlab_integrator);
    integrator.id = "checked";
    integrator.name = "Checked";
    integrator.version = "1.0.0";
    integrator.description = "an integrator for the validator's tests";
    integrator.order = 1;
    integrator.evals_per_step = 1;
    integrator.precisions = 1u << CLOTHLAB_FLOAT64;
    integrator.param_count = static_cast<uint32_t>(params.size());
    integrator.params = params.data();
    integrator.create = create;
    integrator.prepare = prepare;
    integrator.step = step;
    integrator.destroy = destroy;
    descriptor.abi_version = {CLOTHLAB_ABI_VERSION_MAJOR, CLOTHLAB_ABI_VERSION_MINOR};
    descriptor.struct_size = sizeof(clothlab_plugin_descriptor);
    descriptor.integrator_count = 1;
    descriptor.library_name = "checked-library";
    descriptor.library_version = "1.0.0";
    descriptor.integrators = list.data();
  }
  OneIntegrator(const OneIntegrator&) = delete;
  OneIntegrator& operator=(const OneIntegrator&) = delete;

  std::vector<clothlab_param_spec> params;
  clothlab_integrator integrator{};
  std::array<const clothlab_integrator*, 1> list{&integrator};
  clothlab_plugin_descriptor descriptor{};
};

std::vector<std::string> described(const std::vector<DescriptorFinding>& findings) {
  std::vector<std::string> lines;
  for (const DescriptorFinding& finding : findings) lines.push_back(describe(finding));
  return lines;
}

TEST(DescriptorFindings, ASoundDescriptorHasNone) {
  const OneIntegrator library({int_spec("substeps", 1, 1, 64), bool_spec("verbose", 0, 1)});
  EXPECT_TRUE(descriptor_findings(library.descriptor).empty());
  EXPECT_EQ(descriptor_refusal(library.descriptor), "");
}

TEST(DescriptorFindings, TwoFaultsGiveTwoFindingsAndTheLoaderRefusesTheFirst) {
  const OneIntegrator library({int_spec("substeps", 2.5, 1, 64), bool_spec("verbose", 0, 2)});
  const std::vector<DescriptorFinding> findings = descriptor_findings(library.descriptor);
  ASSERT_EQ(findings.size(), 2u) << ::testing::PrintToString(described(findings));
  EXPECT_EQ(findings[0].part, DescriptorPart::params);
  EXPECT_EQ(findings[0].component, "checked");
  EXPECT_EQ(findings[0].field, "params.substeps.default_value");
  EXPECT_EQ(findings[0].value, "2.5");
  EXPECT_EQ(findings[0].allowed, "int in [1, 64]");
  EXPECT_EQ(describe(findings[1]),
            "integrator checked: params.verbose.range = [0, 2], allowed [0, 1] for a bool");
  EXPECT_EQ(descriptor_refusal(library.descriptor), describe(findings[0]));
}

TEST(DescriptorFindings, EveryFaultOfOneComponentIsFound) {
  OneIntegrator library({int_spec("substeps", 0, 1, 64), int_spec("substeps", 1, 1, 64)});
  library.integrator.description = "";
  library.integrator.step = nullptr;
  EXPECT_EQ(described(descriptor_findings(library.descriptor)),
            (std::vector<std::string>{
                "integrator checked: description = \"\", allowed a non-empty string",
                "integrator checked: step = null, allowed a function",
                "integrator checked: params.substeps.default_value = 0, allowed int in [1, 64]",
                "integrator checked: params.substeps.name = \"substeps\", allowed a name no other "
                "parameter of the component has"}));
}

TEST(DescriptorFindings, AnotherMajorIsReadNoFurther) {
  OneIntegrator library({int_spec("substeps", 0, 1, 64)});
  library.descriptor.abi_version = {CLOTHLAB_ABI_VERSION_MAJOR + 1, 0};
  const std::vector<DescriptorFinding> findings = descriptor_findings(library.descriptor);
  ASSERT_EQ(findings.size(), 1u);
  EXPECT_EQ(findings[0].field, "abi_version");
}

TEST(DescriptorFindings, ALibraryWithoutComponentsIsRefused) {
  OneIntegrator library({});
  library.descriptor.integrator_count = 0;
  EXPECT_EQ(described(descriptor_findings(library.descriptor)),
            (std::vector<std::string>{"library: integrator_count + scenario_count = 0, allowed "
                                      "at least 1 (a library provides a component)"}));
}

TEST(DescriptorFindings, AComponentWithoutIdIsTheLibrarys) {
  OneIntegrator library({});
  library.integrator.id = nullptr;
  const std::vector<DescriptorFinding> findings = descriptor_findings(library.descriptor);
  ASSERT_EQ(findings.size(), 1u);
  EXPECT_EQ(describe(findings[0]), "library: integrators[0].id = null, allowed [a-z0-9_-]+");
}

TEST(DescriptorFindings, TheDescriptionStaysOneLine) {
  OneIntegrator library({});
  library.integrator.id = "two\nlines";
  ASSERT_EQ(descriptor_findings(library.descriptor).size(), 1u);
  EXPECT_EQ(describe(descriptor_findings(library.descriptor)[0]),
            "integrator two\\nlines: id = \"two\\nlines\", allowed [a-z0-9_-]+");
}

}  // namespace
}  // namespace clothlab::host
