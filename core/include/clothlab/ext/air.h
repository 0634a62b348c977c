/*
 * Scenario extension "clothlab.air/1" (ABI 1.3): the air the cloth moves through, as a drag and
 * lift model on each triangle from the relative air velocity v_rel = wind_velocity - v_tri (v_tri
 * the mean of its corners' velocities), after the panel models of NvCloth and Newton. For a
 * triangle of area A and unit normal n, cos(theta) = n . v_rel / |v_rel|:
 *   drag  D = 1/2 density drag_coefficient A |cos(theta)| |v_rel|^2, along v_rel (the area the
 *         stream meets times its dynamic pressure)
 *   lift  L = 1/2 density lift_coefficient A cos(theta) sin(theta) |v_rel|^2, perpendicular to
 *         v_rel in the plane of v_rel and n, away from the side the stream comes from
 * a third of each to every corner. Both are independent of the normal's orientation and vanish
 * for a triangle moving with the wind or lying edge-on in the stream. The seed's pressure model
 * (clothlab_scene's wind_direction and wind_strength) is separate and adds to this one.
 *
 * Velocity: the host evaluates the model at the velocities a force evaluation is given (those of
 * eval_acceleration, eval_acceleration_at, step_rkn's stages) and, where a call gives none
 * (clothlab.external-forces/1, which takes no velocity, or v = NULL from an integrator without
 * CLOTHLAB_INTEGRATOR_USES_VELOCITY_FORCES), at the system's current v: the air then lags by
 * what the integrator has not yet written back. The Jacobian extensions leave the air out (it is
 * treated explicitly, as the wind's position dependence is).
 */
#ifndef CLOTHLAB_EXT_AIR_H
#define CLOTHLAB_EXT_AIR_H

#include <clothlab/plugin.h>

#ifdef __cplusplus
extern "C" {
#endif

#define CLOTHLAB_EXT_AIR "clothlab.air/1"

typedef struct clothlab_air {
  uint32_t struct_size;
  uint32_t reserved0;
  double wind_velocity[3]; /* m/s, the air's velocity; finite */
  double density;          /* kg/m^3, >= 0; 0 = no air (the scene has none) */
  double drag_coefficient; /* >= 0 */
  double lift_coefficient; /* >= 0 */
} clothlab_air;

typedef struct clothlab_air_extension {
  /* The scene's air, fixed for the instance's lifetime. The host sets out->struct_size before
   * the call. */
  clothlab_status (*describe)(void *instance, clothlab_air *out, clothlab_message *error);
} clothlab_air_extension;

#ifdef __cplusplus
}
#endif

#endif /* CLOTHLAB_EXT_AIR_H */
