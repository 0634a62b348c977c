/*
 * Host extension "clothlab.topology/1": the cloth's springs, triangles, adjacency and
 * colourings as plain arrays, for methods that treat springs themselves (XPBD,
 * projective dynamics, vertex block descent) or build a global matrix.
 *
 * Lifetime: every array is owned by the host and valid until the system is destroyed;
 * it never changes while the system lives. Thread rule: `get` may be called from any
 * thread; its first call per system may allocate, so call it from `prepare`.
 */
#ifndef CLOTHLAB_EXT_TOPOLOGY_H
#define CLOTHLAB_EXT_TOPOLOGY_H

#include <clothlab/plugin.h>

#ifdef __cplusplus
extern "C" {
#endif

#define CLOTHLAB_EXT_TOPOLOGY "clothlab.topology/1"

#define CLOTHLAB_SPRING_STRUCTURAL 0u
#define CLOTHLAB_SPRING_SHEAR 1u
#define CLOTHLAB_SPRING_FLEXION 2u

typedef struct clothlab_topology {
  uint32_t struct_size;
  uint32_t particle_count; /* n, as in clothlab_system */

  /* Springs, spring_count entries each. A spring joins particles first[k] < second[k];
   * springs whose family has ks = kd = 0 are left out. Forces: Hooke ks (N/m) about
   * rest_length (m) plus damping kd (N s/m) along the spring, as eval_acceleration
   * computes them. Springs between two pinned particles are included. */
  uint32_t spring_count;
  uint32_t triangle_count;
  const uint32_t *first;
  const uint32_t *second;
  const double *rest_length;
  const double *ks;
  const double *kd;
  const uint8_t *family; /* CLOTHLAB_SPRING_* */

  /* Triangles of the cloth surface (the ones wind acts on), 3 * triangle_count particle
   * indices, counter-clockwise seen from the side the normal points to. */
  const uint32_t *triangles;

  /* Particle -> spring adjacency (CSR): the springs touching particle i are
   * adjacent_springs[adjacency_offsets[i] .. adjacency_offsets[i + 1]), ascending.
   * adjacency_offsets has n + 1 entries. */
  const uint32_t *adjacency_offsets;
  const uint32_t *adjacent_springs;

  /* Springs into independent sets: no two springs of a colour share a particle.
   * Colour c holds spring_color_members[spring_color_offsets[c] .. [c + 1]), ascending.
   * On the Provot grid: 12 colours (6 stencil directions x 2 parities). */
  uint32_t spring_color_count;
  uint32_t reserved0;
  const uint32_t *spring_color_offsets; /* spring_color_count + 1 */
  const uint32_t *spring_color_members; /* spring_count spring indices */

  /* Particles into independent sets: no spring joins two particles of a colour. Pinned
   * particles are included (skip them by inverse mass). On the Provot grid:
   * colour (row + 2 col) mod 5. */
  uint32_t particle_color_count;
  uint32_t reserved1;
  const uint32_t *particle_color_offsets; /* particle_color_count + 1 */
  const uint32_t *particle_color_members; /* n particle indices */
} clothlab_topology;

typedef struct clothlab_topology_extension {
  /* Fills *out (the caller sets out->struct_size). CLOTHLAB_ERROR_OUT_OF_MEMORY when the
   * first call cannot allocate. */
  clothlab_status (*get)(void *context, clothlab_topology *out);
} clothlab_topology_extension;

#ifdef __cplusplus
}
#endif

#endif /* CLOTHLAB_EXT_TOPOLOGY_H */
