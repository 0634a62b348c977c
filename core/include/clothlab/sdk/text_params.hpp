// Text parameters (clothlab.text-parameters/1) on the plugin side: the specs a component
// declares and the validated values its constructor reads.
//
//   static constexpr std::array text_params{
//       sdk::text_param("file", "", 4096, CLOTHLAB_TEXT_PATH, "the mesh file to read")};
//   Impl(const sdk::Params& values, const sdk::TextParams& texts);   // texts.text("file")
#pragma once

#include <clothlab/ext/text_parameters.h>

#include <clothlab/sdk/error.hpp>
#include <cstring>
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
  // The specs' defaults: what a host that does not know the extension gets.
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

}  // namespace clothlab::sdk
