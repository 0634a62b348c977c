/*
 * Host extension "clothlab.external-forces/1": the acceleration of the external forces
 * alone (gravity and wind on the triangles, no springs), for methods that treat the
 * springs themselves (XPBD, projective dynamics, VBD). a_ext + the spring acceleration
 * = eval_acceleration. Thread rule: as eval_acceleration. Never allocates.
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

#ifdef __cplusplus
}
#endif

#endif /* CLOTHLAB_EXT_EXTERNAL_FORCES_H */
