// Text parameters (clothlab.text-parameters/1) on the plugin side: the specs a component
// declares, the validated values its constructor reads, and the extension table.
//
//   static constexpr std::array text_params{
//       sdk::text_param("file", "", 4096, CLOTHLAB_TEXT_PATH, "the mesh file to read")};
//   Impl(const sdk::Params& values, const sdk::TextParams& texts);   // texts.text("file")
//   explicit Impl(const sdk::Params& values) : Impl(values, sdk::TextParams(text_params)) {}
//   static const void* extension(std::string_view id) noexcept {
//     return id == CLOTHLAB_EXT_TEXT_PARAMETERS ? sdk::text_parameters_table<Impl>() : nullptr;
//   }
// The one-argument constructor serves a host without the extension: every text its default.
#pragma once

#include <clothlab/ext/text_parameters.h>

#include <clothlab/sdk.hpp>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace clothlab::sdk {

constexpr clothlab_text_param_spec text_param(const char* name, const char* fallback,
                                              uint32_t max_length, uint32_t flags,
                                              const char* help) {
  return {sizeof(clothlab_text_param_spec), flags, name, help, fallback, max_length, 0};
}

class TextParams {
 public:
  // The specs' defaults.
  explicit TextParams(std::span<const clothlab_text_param_spec> specs) : specs_(specs) {
    for (const clothlab_text_param_spec& spec : specs) texts_.emplace_back(spec.default_text);
  }

  TextParams(std::span<const clothlab_text_param_spec> specs, const char* const* texts,
             uint32_t count)
      : specs_(specs) {
    if (count != specs.size())
      throw Error(CLOTHLAB_ERROR_INVALID_ARGUMENT, "expected " + std::to_string(specs.size()) +
                                                       " text values, got " +
                                                       std::to_string(count));
    if (count > 0 && texts == nullptr)
      throw Error(CLOTHLAB_ERROR_INVALID_ARGUMENT, "text values are null");
    for (uint32_t i = 0; i < count; ++i) {
      if (texts[i] == nullptr)
        throw Error(CLOTHLAB_ERROR_INVALID_ARGUMENT,
                    "parameter " + std::string(specs[i].name) + ": text is null");
      const std::string_view text(texts[i]);
      if (text.size() > specs[i].max_length || text.find_first_of("\r\n") != text.npos)
        throw Error(CLOTHLAB_ERROR_INVALID_ARGUMENT,
                    "parameter " + std::string(specs[i].name) + ": text longer than " +
                        std::to_string(specs[i].max_length) + " bytes or with a line break");
      texts_.emplace_back(text);
    }
  }

  const std::string& text(std::string_view name) const {
    for (size_t i = 0; i < specs_.size(); ++i)
      if (name == specs_[i].name) return texts_[i];
    throw Error(CLOTHLAB_ERROR_INTERNAL,
                "plugin reads undeclared text parameter " + std::string(name));
  }

 private:
  std::span<const clothlab_text_param_spec> specs_;
  std::vector<std::string> texts_;
};

// The extension table of a component class with `params`, `text_params` and a constructor
// Impl(const Params&, const TextParams&).
template <class Impl>
const clothlab_text_parameters_extension* text_parameters_table() {
  static const clothlab_text_parameters_extension table{
      sizeof(clothlab_text_parameters_extension), static_cast<uint32_t>(Impl::text_params.size()),
      Impl::text_params.data(),
      [](const clothlab_param_value* values, uint32_t count, const char* const* texts,
         uint32_t text_count, void** out, clothlab_message* error) -> clothlab_status {
        return guarded(error, [&] {
          if (out == nullptr) throw Error(CLOTHLAB_ERROR_INVALID_ARGUMENT, "out_instance is null");
          *out = new Impl(Params(Impl::params, values, count),
                          TextParams(Impl::text_params, texts, text_count));
        });
      }};
  return &table;
}

}  // namespace clothlab::sdk
