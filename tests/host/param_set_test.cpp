#include <gtest/gtest.h>

#include <clothlab/host/errors.hpp>
#include <clothlab/host/param_set.hpp>
#include <clothlab/host/param_text.hpp>
#include <clothlab/sdk.hpp>

namespace clothlab::host {
namespace {

constexpr std::array specs{
    sdk::real_param("ks", 20.0, 0.0, 100.0, "N/m", "stiffness"),
    sdk::int_param("rows", 10, 1, 300, "rows"),
    sdk::bool_param("pinned", false, "pin"),
    sdk::vec3_param("gravity", {0.0, -9.81, 0.0}, -50.0, 50.0, "m/s^2", "gravity"),
};

// The InputError message of set(key, text), or "" if it was accepted.
std::string set_error(ParamSet& params, const std::string& key, const std::string& text) {
  try {
    params.set(key, text, "cfg.yaml:3:7");
  } catch (const InputError& error) {
    return error.what();
  }
  return "";
}

TEST(ParamSet, StartsFromTheDefaults) {
  const ParamSet params(specs, "scenario");
  ASSERT_EQ(params.values().size(), 4u);
  EXPECT_EQ(params.value("ks").v[0], 20.0);
  EXPECT_EQ(params.value("rows").v[0], 10.0);
  EXPECT_EQ(params.value("pinned").v[0], 0.0);
  EXPECT_EQ(params.value("gravity").v[1], -9.81);
}

TEST(ParamSet, ParsesEachType) {
  ParamSet params(specs, "scenario");
  params.set("ks", "1.5e1", "--set");
  params.set("rows", "300", "--set");
  params.set("pinned", "true", "--set");
  params.set("gravity", "1,2,3", "--set");
  EXPECT_EQ(params.value("ks").v[0], 15.0);
  EXPECT_EQ(params.value("rows").v[0], 300.0);
  EXPECT_EQ(params.value("pinned").v[0], 1.0);
  EXPECT_EQ(params.value("gravity").v[2], 3.0);
  params.set("pinned", "0", "--set");
  params.set("gravity", "[0, -1.5, 0]", "--set");
  EXPECT_EQ(params.value("pinned").v[0], 0.0);
  EXPECT_EQ(params.value("gravity").v[1], -1.5);
}

TEST(ParamSet, OutOfRangeNamesSourceKeyValueAndRange) {
  ParamSet params(specs, "scenario");
  const std::string message = set_error(params, "ks", "150");
  EXPECT_EQ(message,
            "cfg.yaml:3:7: scenario.ks = 150: out of range; allowed: real in [0, 100] N/m");
  EXPECT_EQ(params.value("ks").v[0], 20.0);  // unchanged
}

TEST(ParamSet, RejectsValuesOfTheWrongType) {
  ParamSet params(specs, "scenario");
  EXPECT_NE(set_error(params, "ks", "stiff").find("not a finite number"), std::string::npos);
  EXPECT_NE(set_error(params, "ks", "nan").find("not a finite number"), std::string::npos);
  EXPECT_NE(set_error(params, "rows", "2.5").find("not a whole number"), std::string::npos);
  EXPECT_NE(set_error(params, "pinned", "yes").find("true/false/1/0"), std::string::npos);
  EXPECT_NE(set_error(params, "gravity", "[1, 2]").find("three finite numbers"), std::string::npos);
  EXPECT_NE(set_error(params, "gravity", "[1, 2, 60]").find("out of range"), std::string::npos);
  EXPECT_NE(set_error(params, "rows", "0").find("int in [1, 300]"), std::string::npos);
}

TEST(ParamSet, UnknownKeyListsTheValidOnes) {
  ParamSet params(specs, "integrator");
  EXPECT_EQ(set_error(params, "kz", "1"),
            "cfg.yaml:3:7: unknown parameter integrator.kz (did you mean integrator.ks?); valid: "
            "integrator.ks, "
            "integrator.rows, integrator.pinned, integrator.gravity");
}

TEST(ParamSet, AComponentWithoutParametersSaysSo) {
  ParamSet params({}, "integrator");
  EXPECT_EQ(set_error(params, "damping", "1"),
            "cfg.yaml:3:7: unknown parameter integrator.damping; the integrator takes no "
            "parameters");
}

}  // namespace
}  // namespace clothlab::host

// Item 6 of issue 12: a sweep axis value 1e1 was keyed as 10, then failed as "not a whole
// number". An int reads any spelling of a whole number; a fraction is still refused.
TEST(ParamText, AnIntReadsEverySpellingOfAWholeNumber) {
  clothlab_param_spec spec{};
  spec.struct_size = sizeof spec;
  spec.type = CLOTHLAB_PARAM_INT;
  for (const char* text : {"10", "1e1", "10.0", "+10", " 10 "}) {
    const clothlab::host::ParsedParam parsed = clothlab::host::parse_param_text(spec, text);
    ASSERT_TRUE(parsed.value.has_value()) << text << ": " << parsed.problem;
    EXPECT_EQ(parsed.value->v[0], 10.0) << text;
    EXPECT_EQ(clothlab::host::canonical_value(text), "10") << text;
  }
  for (const char* text : {"1.5", "1e-1", "0x10", "ten", "1e400"})
    EXPECT_EQ(clothlab::host::parse_param_text(spec, text).problem, "not a whole number") << text;
}
