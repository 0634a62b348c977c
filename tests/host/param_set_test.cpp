#include <gtest/gtest.h>

#include <clothlab/host/errors.hpp>
#include <clothlab/host/param_set.hpp>
#include <clothlab/host/param_text.hpp>
#include <clothlab/sdk.hpp>
#include <clothlab/sdk/text_params.hpp>
#include <filesystem>

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

namespace clothlab::host {
namespace {

constexpr std::array text_specs{
    sdk::text_param("file", "", 64, CLOTHLAB_TEXT_PATH, "a file"),
    sdk::text_param("label", "none", 8, 0, "a name"),
};

TEST(ParamSetText, StartsFromTheDefaultsAndStoresText) {
  ParamSet params(specs, "scenario", text_specs);
  EXPECT_EQ(params.texts(), (std::vector<std::string>{"", "none"}));
  params.set("label", "cape 2", "--set");
  EXPECT_EQ(params.text("label"), "cape 2");
  EXPECT_EQ(params.values().size(), 4u);  // the numbers are unchanged
}

// A relative path is taken from the configuration file's folder when the key came from one,
// else from the working directory; an absolute path stays as it is.
TEST(ParamSetText, ResolvesRelativePathsAgainstTheConfigFolderOrTheWorkingDirectory) {
  ParamSet params(specs, "scenario", text_specs);
  params.set("file", "meshes/cape.obj", "/home/u/configs/run.yaml:4:9");
  EXPECT_EQ(params.text("file"), "/home/u/configs/meshes/cape.obj");
  params.set("file", "../assets/cape.obj", "/home/u/configs/run.yaml:4:9");
  EXPECT_EQ(params.text("file"), "/home/u/assets/cape.obj");
  params.set("file", "cape.obj", "--set");
  EXPECT_EQ(params.text("file"), (std::filesystem::current_path() / "cape.obj").string());
  params.set("file", "meshes/cape.obj", "run.yaml:4:9");  // a config in the working directory
  EXPECT_EQ(params.text("file"), (std::filesystem::current_path() / "meshes/cape.obj").string());
  params.set("file", "/data/cape.obj", "/home/u/configs/run.yaml:4:9");
  EXPECT_EQ(params.text("file"), "/data/cape.obj");
  params.set("label", "a/b", "/home/u/configs/run.yaml:5:9");
  EXPECT_EQ(params.text("label"), "a/b");  // no path: as written
}

TEST(ParamSetText, RefusesTooLongTextAndLineBreaksNamingTheSourceAndKey) {
  ParamSet params(specs, "scenario", text_specs);
  EXPECT_EQ(set_error(params, "label", "123456789"),
            "cfg.yaml:3:7: scenario.label = 123456789: 9 bytes; allowed: text of at most 8 bytes "
            "on one line");
  EXPECT_EQ(set_error(params, "label", "a\nb"),
            "cfg.yaml:3:7: scenario.label = a\\nb: a line break or NUL; allowed: text of at most 8 "
            "bytes on one line");
  EXPECT_EQ(params.text("label"), "none");
}

TEST(ParamSetText, AnUnknownKeyListsTheTextKeysToo) {
  ParamSet params(specs, "scenario", text_specs);
  const std::string message = set_error(params, "fil", "x");
  EXPECT_NE(message.find("did you mean scenario.file?"), std::string::npos) << message;
  EXPECT_NE(message.find("scenario.gravity, scenario.file, scenario.label"), std::string::npos)
      << message;
}

}  // namespace
}  // namespace clothlab::host
