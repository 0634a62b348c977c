// The checks a cloth mesh's geometry must pass before it is simulated.
#pragma once

#include <string>

#include "triangle_mesh.hpp"

namespace clothlab::builtin {

// Throws sdk::Error (invalid argument) "<source>: <what is wrong>" for the first problem: what
// the host's mesh check refuses (sdk::validate_triangle_mesh: an empty mesh, a non-finite
// coordinate, a corner index out of range, a degenerate or zero-area triangle, an edge of more
// than two triangles), or two triangles that wind their shared edge the same way (the mesh has
// no one front side).
void check_mesh_geometry(const TriangleMesh& mesh, const std::string& source);

}  // namespace clothlab::builtin
