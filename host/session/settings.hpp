// The program's settings are the configuration model's (clothlab/config).
#pragma once

#include <clothlab/config/setting.hpp>

namespace clothlab::cli {

using config::canonical_key;
using config::check_one_length;
using config::Setting;

}  // namespace clothlab::cli
