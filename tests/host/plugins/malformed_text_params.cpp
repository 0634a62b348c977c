// A scenario whose clothlab.text-parameters/1 spec has no default text (a null pointer): the
// host must refuse it with an error naming the component, not read through the null.
#include <clothlab/ext/text_parameters.h>

#include <array>
#include <clothlab/sdk.hpp>
#include <string_view>

namespace {

struct MalformedTextParams {
  static constexpr const char* id = "test-malformed-text";
  static constexpr const char* name = "Malformed text parameters";
  static constexpr const char* version = "0.1.0";
  static constexpr const char* description = "a text parameter spec with a null default";
  static constexpr std::array<clothlab_param_spec, 0> params{};

  explicit MalformedTextParams(const clothlab::sdk::Params&) {}

  void describe(clothlab_scene& scene) const {
    scene.rows = scene.cols = 2;
    scene.width = scene.height = 1.0;
    scene.col_axis[0] = 1.0;
    scene.row_axis[1] = -1.0;
    scene.total_mass = 1.0;
  }

  static const void* extension(std::string_view extension_id) noexcept {
    static const clothlab_text_param_spec spec{
        sizeof(clothlab_text_param_spec), 0, "file", "a file", nullptr, 64, 0};
    static const clothlab_text_parameters_extension table{
        sizeof(clothlab_text_parameters_extension), 1, &spec,
        [](const clothlab_param_value*, uint32_t, const char* const*, uint32_t, void**,
           clothlab_message*) -> clothlab_status { return CLOTHLAB_ERROR_INTERNAL; }};
    return extension_id == CLOTHLAB_EXT_TEXT_PARAMETERS ? &table : nullptr;
  }
};

}  // namespace

CLOTHLAB_PLUGIN_ENTRY("clothlab-test-malformed-text", "0.1.0", clothlab::sdk::integrators<>,
                      clothlab::sdk::scenarios<MalformedTextParams>)
