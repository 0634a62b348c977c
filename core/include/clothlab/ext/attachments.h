/*
 * Scenario extension "clothlab.attachments/1" (ABI 1.3): particles attached to something that
 * moves (a character's shoulders, a hand, a flag pole carried along). Each attached particle
 * follows a target the scenario gives, position and velocity, at any time t, so a scene can
 * drag its cloth along a script. The host pins every attached particle (inverse mass 0, as the
 * scene's own pins) and moves it to its target through clothlab.attachment-targets/1.
 *
 * The host reads the targets at every step start before the run: a particle index out of range,
 * a non-finite target, or a target that jumps (moves farther between two step starts than its
 * velocities there allow) is bad input, refused before the first step.
 */
#ifndef CLOTHLAB_EXT_ATTACHMENTS_H
#define CLOTHLAB_EXT_ATTACHMENTS_H

#include <clothlab/plugin.h>

#ifdef __cplusplus
extern "C" {
#endif

#define CLOTHLAB_EXT_ATTACHMENTS "clothlab.attachments/1"

typedef struct clothlab_attachments_extension {
  /* How many particles are attached; fixed for the instance's lifetime. */
  uint32_t (*count)(void *instance);
  /* Writes the `count` attached particle indices (each < rows x cols) to out. */
  clothlab_status (*particles)(void *instance, uint32_t *out, clothlab_message *error);
  /* The targets at time t (s, from the run's start): positions (m) and velocities (m/s), 3 x
   * count each, particle-major (positions[3 k + axis] for particles[k]). Called during steps,
   * possibly at substep times: must not allocate and must not change the instance. */
  clothlab_status (*targets)(void *instance, double t, double *positions, double *velocities,
                             clothlab_message *error);
} clothlab_attachments_extension;

#ifdef __cplusplus
}
#endif

#endif /* CLOTHLAB_EXT_ATTACHMENTS_H */
