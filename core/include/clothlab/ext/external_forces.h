/*
 * Host extension "clothlab.external-forces/1": the acceleration of the external forces
 * alone (gravity and wind on the triangles, no springs), for methods that treat the
 * springs themselves (XPBD, projective dynamics, VBD). a_ext + the spring acceleration
 * = eval_acceleration. Thread rule: as eval_acceleration. Never allocates.
 *
 * "clothlab.external-forces/2" (ABI 1.3) is revision 1 with the same accelerations for a
 * range of grid rows (clothlab.grid/1's rows), so that a method sweeping the grid a row at a
 * time computes them a few rows ahead of where it reads them instead of in a pass of their
 * own over the whole cloth. A host offers /2 only where it has clothlab.grid/1 and a range of
 * rows costs in proportion to its rows; a host offering /2 offers /1 too.
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

/* Revision 2: revision 1's calls, then the rows call and whether the air reads velocities. */
typedef struct clothlab_external_forces_2_extension {
  clothlab_status (*acceleration)(void *context, double t, const void *x, void *a);
  int32_t (*depends_on_position)(void *context);
  /* a on the particles of grid rows [row_begin, row_end), bit for bit what `acceleration`
   * writes there; no other entry of a is written. Reads x on rows row_begin - 1 to row_end
   * (and, see depends_on_velocity, the system's velocities there). slot < the count of
   * clothlab.threads/1: calls with different slots may run at the same time on disjoint
   * ranges, calls with one slot may not. CLOTHLAB_ERROR_NUMERICAL when a value is not
   * finite, CLOTHLAB_ERROR_INVALID_ARGUMENT for a range past the last row or a slot out of
   * range. */
  clothlab_status (*acceleration_rows)(void *context, double t, const void *x, void *a,
                                       uint32_t row_begin, uint32_t row_end, uint32_t slot);
  /* 1 when the external acceleration also reads the system's velocities (air drag and
   * lift): then a caller that changes v during its sweep must not compute rows ahead. */
  int32_t (*depends_on_velocity)(void *context);
} clothlab_external_forces_2_extension;

#ifdef __cplusplus
}
#endif

#endif /* CLOTHLAB_EXT_EXTERNAL_FORCES_H */
