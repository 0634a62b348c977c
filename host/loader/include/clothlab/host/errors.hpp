// The host's error kinds; each maps to one exit code of the clothlab program.
#pragma once

#include <clothlab/plugin.h>

#include <filesystem>
#include <stdexcept>
#include <string>
#include <string_view>

namespace clothlab::host {

// Bad user input: command line, config file or parameter value (exit code 1).
class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// A plugin library that cannot be found, opened or accepted (exit code 2).
class PluginLoadError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// "cannot load plugin PATH: WHY", and " (plugin search path: SEARCHED)" when that is given.
PluginLoadError cannot_load(const std::filesystem::path& path, const std::string& why,
                            std::string_view searched = {});

// A plugin call that returned an error status (exit code 2, or 3 for a numerical failure).
class PluginError : public std::runtime_error {
 public:
  PluginError(clothlab_status status, const std::string& message)
      : std::runtime_error(message), status_(status) {}
  clothlab_status status() const noexcept { return status_; }

 private:
  clothlab_status status_;
};

// The text with line breaks and other control bytes written as \n, \r, \xNN, so an error that
// echoes a value (threads: "a\nb") stays one line.
std::string one_line(std::string_view text);

// "invalid argument", "numerical failure", ... for a status code.
const char* status_name(clothlab_status status);

}  // namespace clothlab::host
