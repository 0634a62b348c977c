// Single-run config files are read by the configuration model (clothlab/config).
#pragma once

#include <clothlab/config/yaml_settings.hpp>

#include "settings.hpp"

namespace clothlab::cli {

using config::read_config_file;

}  // namespace clothlab::cli
