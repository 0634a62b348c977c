/*
 * Host extension "clothlab.contacts/1" (ABI 1.3): keeps the cloth out of the scene's colliders
 * (clothlab.colliders/1 or /2). Over a step each collider moves at the velocity it has at the
 * step's start. For each active particle of (x, v) within a collider's thickness of its surface,
 * at the colliders' poses at time t (the step's or substep's end):
 *   position  pushed out along the surface normal to the thickness
 *   velocity  taken relative to the body's surface there: the normal velocity into the body
 *             removed (inelastic contact), and the tangential velocity reduced by friction x the
 *             normal velocity removed (Coulomb), at most to the body's
 * A particle that moved through a collider, or past its middle, or that the collider passed,
 * since the step's start or the last resolve (its straight path relative to the body crossed the
 * collider: the surface nearest its end faces away from the one nearest its start) is first put
 * back where that path entered the thickness, so neither a fast particle nor a fast collider
 * tunnels through a thin collider however large the step.
 * Force-based integrators call it after each step or substep; position-based ones after each
 * substep's projection. An integrator that does so declares CLOTHLAB_TRAIT_RESOLVES_CONTACTS
 * (clothlab.integrator-traits/1): the host refuses a scene with colliders for any other.
 * The host offers the extension on every cloth, also one without colliders (resolve is then a
 * no-op), so an integrator need not ask.
 */
#ifndef CLOTHLAB_EXT_CONTACTS_H
#define CLOTHLAB_EXT_CONTACTS_H

#include <clothlab/plugin.h>

#ifdef __cplusplus
extern "C" {
#endif

#define CLOTHLAB_EXT_CONTACTS "clothlab.contacts/1"

typedef struct clothlab_contacts_extension {
  /* x and v are vectors of the system (usually system->x and system->v), changed in place on
   * active particles only. Never allocates. Returns CLOTHLAB_ERROR_NUMERICAL when a position
   * or velocity it meets is not finite. */
  clothlab_status (*resolve)(void* context, double t, void* x, void* v);
} clothlab_contacts_extension;

#ifdef __cplusplus
}
#endif

#endif /* CLOTHLAB_EXT_CONTACTS_H */
