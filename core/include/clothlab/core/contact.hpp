// Contact of one particle with the colliders (clothlab/ext/contacts.h): pushed out along the
// surface normal to the thickness, the normal velocity into the body removed, Coulomb friction
// on the tangential velocity.
#pragma once

#include <clothlab/core/collider.hpp>
#include <span>

namespace clothlab {

// Resolves one particle against every collider in turn; returns whether any touched it.
// Friction: the tangential velocity shrinks by friction x the normal velocity removed (the
// normal impulse per unit mass), and stops at 0; so a particle sliding on a surface under
// gravity g decelerates by friction x g, as Coulomb's law has it.
bool resolve_contact(std::span<const Collider> colliders, Vec3& x, Vec3& v);

// The same for a particle that moved from `from` to x in the last step or substep, so that a
// fast one cannot pass through a thin collider (a capsule's arm) or past its middle between two
// resolutions: when the nearest surface at x faces away from the one at `from` and the straight
// path entered the collider's thickness, the particle goes back to where the path first entered
// it and is resolved there. The path is searched by conservative advancement (the signed distance
// bounds how far it may go untouched), in at most 256 advances: a collider thinner than 1/256 of
// the path can still be missed.
bool resolve_swept_contact(std::span<const Collider> colliders, const Vec3& from, Vec3& x, Vec3& v);

// How deep a point lies inside any collider (0 when outside all): the penetration of the
// surface itself, not of the thickness band.
double penetration_depth(std::span<const Collider> colliders, const Vec3& x);

// How far a point lies past a collider's thickness into it, the largest over the colliders
// (0 when no collider holds it deeper than its thickness): each against its own thickness.
double depth_past_thickness(std::span<const Collider> colliders, const Vec3& x);

// Both depths above from one distance per collider.
struct ContactDepths {
  double penetration = 0, past_thickness = 0;
};
ContactDepths contact_depths(std::span<const Collider> colliders, const Vec3& x);

}  // namespace clothlab
