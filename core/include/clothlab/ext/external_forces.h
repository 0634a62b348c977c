/*
 * Host extension "clothlab.external-forces/1": the acceleration of the external forces
 * alone (gravity and wind on the triangles, no springs), for methods that treat the
 * springs themselves (XPBD, projective dynamics, VBD). a_ext + the spring acceleration
 * = eval_acceleration. Thread rule: as eval_acceleration. Never allocates.
 *
 * "clothlab.external-forces/2" is its next revision: /1's two functions, unchanged, and the
 * acceleration of a range of particles, so that a method sweeping the cloth in pieces (XPBD's
 * wavefront over the grid rows) takes a piece's external acceleration just before it uses it,
 * while the piece is in cache, and on the thread that uses it, instead of in a pass of its
 * own over the whole cloth. A revision and not an extension of its own: a plugin that wants
 * the ranges wants the other two as well. A host offering /2 keeps offering /1 (the same
 * functions) for the plugins built against it; published structs never grow, so /2 is a
 * struct of its own.
 */
#ifndef CLOTHLAB_EXT_EXTERNAL_FORCES_H
#define CLOTHLAB_EXT_EXTERNAL_FORCES_H

#include <clothlab/plugin.h>

#ifdef __cplusplus
extern "C" {
#endif

#define CLOTHLAB_EXT_EXTERNAL_FORCES "clothlab.external-forces/1"

typedef struct clothlab_external_forces_extension {
  /* a = M^-1 F_external(t, x) on active particles, 0 on pinned ones (m/s^2). x and a are
   * vectors of the system; CLOTHLAB_ERROR_NUMERICAL when a is not finite. */
  clothlab_status (*acceleration)(void *context, double t, const void *x, void *a);
  /* 1 when the external acceleration depends on x (wind), 0 when it is constant
   * (gravity only): then one evaluation serves a whole step. */
  int32_t (*depends_on_position)(void *context);
} clothlab_external_forces_extension;

#define CLOTHLAB_EXT_EXTERNAL_FORCES_2 "clothlab.external-forces/2"

typedef struct clothlab_external_forces_2_extension {
  /* As in /1. */
  clothlab_status (*acceleration)(void *context, double t, const void *x, void *a);
  int32_t (*depends_on_position)(void *context);
  /* Bytes of one workspace for acceleration_range: memory the caller owns, 64-byte aligned,
   * zero-filled by the caller before its first use and written only by the host after that;
   * one workspace per caller running at the same time. Fixed from the system's creation on. */
  uint64_t (*range_workspace_bytes)(void *context);
  /* a = M^-1 F_external(t, x) on the particles [first, first + count) only, bit for bit
   * what acceleration(t, x, a) writes there; a's other elements are left as they are, x is
   * read where the forces need it (for the wind, the triangles at the range). The calls on
   * one workspace form sequences: `resume` 0 starts one, 1 continues the workspace's last
   * one with the same t and x (the same vector): the host may reuse what it computed for
   * earlier ranges of the sequence (the wind on triangles two ranges share), so the caller
   * promises that x has not changed since the sequence began on the particles still to be
   * returned nor on those sharing a triangle with them. Calls on different workspaces may
   * run at the same time on different threads (with disjoint ranges of a); never opens a
   * parallel region of its own. CLOTHLAB_ERROR_INVALID_ARGUMENT for a range past the last
   * particle, a null pointer or x == a; CLOTHLAB_ERROR_NUMERICAL when a is not finite on the
   * range. Never allocates. */
  clothlab_status (*acceleration_range)(void *context, double t, const void *x, void *a,
                                        uint32_t first, uint32_t count, void *workspace,
                                        int32_t resume);
} clothlab_external_forces_2_extension;

#ifdef __cplusplus
}
#endif

#endif /* CLOTHLAB_EXT_EXTERNAL_FORCES_H */
