/*
 * Scenario extension "clothlab.mesh/1" (ABI 1.3): a cloth that is any triangle mesh rather
 * than the rows x cols grid of clothlab_scene.
 *
 * A scenario that offers it still fills clothlab_scene through `describe`: the host takes from
 * it the spring families (ks, kd), total_mass, gravity, wind and the pinned vertex indices, and
 * ignores rows, cols, width, height, origin, col_axis and row_axis. The host derives the springs
 * from the triangles (edges are structural; the two diagonals of a quad split into two triangles
 * are shear; bending springs join the vertices two edges apart along a straight line of edges,
 * or across each shared edge elsewhere): the core's mesh builder, the one the grid builder's
 * springs are tested against.
 *
 * The host calls `describe` once, after the scenario's `describe` and before any step, from the
 * thread that created the instance. The arrays stay valid, unchanged, until the instance is
 * destroyed; the host copies them.
 */
#ifndef CLOTHLAB_EXT_MESH_H
#define CLOTHLAB_EXT_MESH_H

#include <clothlab/plugin.h>

#ifdef __cplusplus
extern "C" {
#endif

#define CLOTHLAB_EXT_MESH "clothlab.mesh/1"

typedef struct clothlab_mesh {
  uint32_t struct_size;
  uint32_t vertex_count;   /* >= 3 */
  uint32_t triangle_count; /* >= 1 */
  uint32_t reserved0;
  /* 3 * vertex_count doubles, x y z of each vertex in metres: the rest shape, and the state
   * the run starts from (at rest). */
  const double *positions;
  /* 3 * triangle_count vertex indices; each triangle's corners in one winding for the whole
   * mesh (its normal's side is the cloth's front). */
  const uint32_t *triangles;
  /* vertex_count masses in kg, or NULL: total_mass spread by area (a third of each triangle's
   * area to each of its corners). */
  const double *masses;
} clothlab_mesh;

typedef struct clothlab_mesh_extension {
  /* The scene's mesh, fixed for the instance's lifetime. The host sets out->struct_size
   * before the call. */
  clothlab_status (*describe)(void *instance, clothlab_mesh *out, clothlab_message *error);
} clothlab_mesh_extension;

#define CLOTHLAB_MESH_SIZE_1 CLOTHLAB_FIELD_END(clothlab_mesh, masses)

#ifdef __cplusplus
}
#endif

#endif /* CLOTHLAB_EXT_MESH_H */
