// `clothlab view RUN_DIR... [--out DIR] [--max-frames N]`.
#pragma once

#include <ostream>

namespace clothlab::viewer {

// argv[0] is "view". Writes the bundle and prints where it is. Throws host::InputError.
void run_view_command(int argc, const char* const argv[], std::ostream& out);

}  // namespace clothlab::viewer
