// xpbd's float row kernel as one SIMD target's entry point, project_float_row_<target>
// (xpbd_row_targets.hpp), compiled once per wider target of a portable build.
#include "simd_namespace.hpp"
#include "xpbd_row_kernel.hpp"

namespace clothlab::builtin {

void CLOTHLAB_SIMD_ENTRY(project_float_row)(const ColorRow<float>& row) { project_row(row); }

}  // namespace clothlab::builtin
