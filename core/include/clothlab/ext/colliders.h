/*
 * Scenario extension "clothlab.colliders/1" (ABI 1.3): rigid analytic bodies the cloth may not
 * enter. Each collider has a fixed shape, defined in its own frame, and a pose (local to world)
 * at any time t, so a scenario can move its colliders along a script.
 * "clothlab.colliders/2" (ABI 1.3) is the same with each pose's velocity (its motion): the host
 * asks a scenario for /2 first and takes /1 when it has none, deriving the velocity of a /1
 * collider from its poses at each step's start and end.
 *
 * Shapes, in the collider's frame:
 *   sphere   centre at the origin, `radius`
 *   capsule  the segment from (-half_length, 0, 0) to (+half_length, 0, 0) swept by a sphere
 *            whose radius goes linearly from `radius` at the -x end to `end_radius` at the +x
 *            end (tapered when they differ; a cone with rounded ends)
 *   plane    the solid half-space y < 0; its surface is y = 0 and its normal +y
 *   box      |x| <= half_extents[0], |y| <= half_extents[1], |z| <= half_extents[2]
 * A particle is kept `thickness` outside the surface; `friction` is the Coulomb coefficient
 * between the cloth and the body.
 */
#ifndef CLOTHLAB_EXT_COLLIDERS_H
#define CLOTHLAB_EXT_COLLIDERS_H

#include <clothlab/plugin.h>

#ifdef __cplusplus
extern "C" {
#endif

#define CLOTHLAB_EXT_COLLIDERS "clothlab.colliders/1"
#define CLOTHLAB_EXT_COLLIDERS_2 "clothlab.colliders/2"

#define CLOTHLAB_COLLIDER_SPHERE 1u
#define CLOTHLAB_COLLIDER_CAPSULE 2u
#define CLOTHLAB_COLLIDER_PLANE 3u
#define CLOTHLAB_COLLIDER_BOX 4u

typedef struct clothlab_collider {
  uint32_t struct_size;
  uint32_t shape;         /* CLOTHLAB_COLLIDER_* */
  double radius;          /* sphere; capsule at its -x end; m, > 0 */
  double end_radius;      /* capsule at its +x end; m, > 0 */
  double half_length;     /* capsule; m, > 0 */
  double half_extents[3]; /* box; m, each > 0 */
  double friction;        /* Coulomb coefficient, >= 0 */
  double thickness;       /* m, >= 0 */
} clothlab_collider;

/* Local to world: world = position + R(orientation) local. */
typedef struct clothlab_pose {
  double position[3];    /* m */
  double orientation[4]; /* unit quaternion (w, x, y, z) */
} clothlab_pose;

typedef struct clothlab_colliders_extension {
  /* How many colliders the scene has; fixed for the instance's lifetime. */
  uint32_t (*count)(void* instance);
  /* Collider `index` < count's shape, friction and thickness. The host sets
   * out->struct_size before the call. */
  clothlab_status (*describe)(void* instance, uint32_t index, clothlab_collider* out,
                              clothlab_message* error);
  /* Collider `index`'s pose at time t (s, from the run's start). */
  clothlab_status (*pose)(void* instance, uint32_t index, double t, clothlab_pose* out,
                          clothlab_message* error);
} clothlab_colliders_extension;

/* A pose and how fast it changes: the velocity of a point p of the body is
 * velocity + angular_velocity x (p - pose.position). */
typedef struct clothlab_collider_motion {
  clothlab_pose pose;
  double velocity[3];         /* of the frame's origin, pose.position; m/s, world frame */
  double angular_velocity[3]; /* rad/s, world frame */
} clothlab_collider_motion;

/* clothlab.colliders/2. Within a step the host moves each collider at the velocity it reports at
 * the step's start. The host refuses a velocity that is not finite, or one that disagrees with
 * the poses: more than 1 m/s (1 rad/s) plus half the larger speed away from the motion between
 * the poses at the step's start and end. */
typedef struct clothlab_colliders_extension_2 {
  /* As in /1. */
  uint32_t (*count)(void* instance);
  /* As in /1. */
  clothlab_status (*describe)(void* instance, uint32_t index, clothlab_collider* out,
                              clothlab_message* error);
  /* Collider `index`'s pose and velocity at time t (s, from the run's start). */
  clothlab_status (*motion)(void* instance, uint32_t index, double t, clothlab_collider_motion* out,
                            clothlab_message* error);
} clothlab_colliders_extension_2;

#ifdef __cplusplus
}
#endif

#endif /* CLOTHLAB_EXT_COLLIDERS_H */
