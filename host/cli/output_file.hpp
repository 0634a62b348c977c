// The program's output files go through the one atomic writer (clothlab/io).
#pragma once

#include <clothlab/io/atomic_file.hpp>

namespace clothlab::cli {

using io::check_output_path;
using io::write_file_atomically;

}  // namespace clothlab::cli
