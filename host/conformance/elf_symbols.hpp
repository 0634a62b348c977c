// Reads the dynamic symbol table of an ELF shared object straight from the file, so the
// export check does not depend on what the dynamic loader chooses to resolve.
#pragma once

#include <string>
#include <vector>

namespace clothlab::conformance {

// Names of the symbols the library defines and exports (global or weak binding, default or
// protected visibility, not undefined). Throws std::runtime_error naming the path when the
// file is not a readable 64-bit ELF object.
std::vector<std::string> exported_symbols(const std::string& path);

}  // namespace clothlab::conformance
