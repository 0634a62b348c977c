/*
 * Host extension "clothlab.attachment-targets/1" (ABI 1.3): moves the scene's attached particles
 * (clothlab.attachments/1) to their targets. Attached particles are pinned (inverse mass 0): the
 * system's vector operations leave them alone, so an integrator moves them itself, once per
 * step or substep, at the time it chooses (docs/reference/abi.md says when each built-in does). An
 * integrator that does so declares CLOTHLAB_TRAIT_MOVES_ATTACHMENTS
 * (clothlab.integrator-traits/1): the host refuses a scene with attachments for any other.
 * The host offers the extension on every cloth, also one without attachments (count is 0 and
 * move a no-op), so an integrator need not ask.
 */
#ifndef CLOTHLAB_EXT_ATTACHMENT_TARGETS_H
#define CLOTHLAB_EXT_ATTACHMENT_TARGETS_H

#include <clothlab/plugin.h>

#ifdef __cplusplus
extern "C" {
#endif

#define CLOTHLAB_EXT_ATTACHMENT_TARGETS "clothlab.attachment-targets/1"

typedef struct clothlab_attachment_targets_extension {
  /* How many particles are attached (0: a static scene; nothing to move). */
  uint32_t (*count)(void *context);
  /* Sets the attached particles' entries of x and v (vectors of the system, usually system->x
   * and system->v) to their targets' positions and velocities at time t. Never allocates.
   * Returns CLOTHLAB_ERROR_NUMERICAL when a target is not finite. */
  clothlab_status (*move)(void *context, double t, void *x, void *v);
} clothlab_attachment_targets_extension;

#ifdef __cplusplus
}
#endif

#endif /* CLOTHLAB_EXT_ATTACHMENT_TARGETS_H */
