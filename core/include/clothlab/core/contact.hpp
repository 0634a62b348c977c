// Contact of one particle with the colliders (clothlab/ext/contacts.h): pushed out along the
// surface normal to the thickness, the normal velocity into the body removed, Coulomb friction
// on the tangential velocity.
#pragma once

#include <clothlab/core/collider.hpp>
#include <span>

namespace clothlab {

// Resolves one particle against every collider in turn; returns whether any touched it.
// The response acts on the particle's velocity relative to the body's surface at the contact
// (Collider::velocity_at): the relative velocity into the body is removed, and friction shrinks
// the relative tangential velocity by friction x the normal velocity removed (the normal impulse
// per unit mass), stopping at the body's; so a particle sliding on a surface under gravity g
// decelerates by friction x g relative to it, as Coulomb's law has it, and a particle resting on
// a moving body is carried with it.
bool resolve_contact(std::span<const Collider> colliders, Vec3& x, Vec3& v);

// The same for a particle that moved from `from` to x since the last resolution, while each
// collider moved from before[k] to now[k] (the same colliders at the two times), so that neither
// a fast particle nor a fast collider passes through a thin collider (a capsule's arm, a blade)
// or past its middle between two resolutions. The path is taken relative to the body: its start
// is carried with the body to now[k]'s pose; when the nearest surface at x faces away from the
// one at that start and the straight path between them entered the collider's thickness, the
// particle goes back to where the path first entered it and is resolved there. The path is
// searched by conservative advancement (the signed distance bounds how far it may go untouched),
// in at most 256 advances: a collider thinner than 1/256 of the relative path can still be missed.
bool resolve_swept_contact(std::span<const Collider> before, std::span<const Collider> now,
                           const Vec3& from, Vec3& x, Vec3& v);

// Whether the path from `from` (colliders at `before`) to `to` (colliders at `now`), relative
// to a collider, passed through it or past its middle: the test resolve_swept_contact acts on,
// which finds a particle that tunnelled.
bool crossed_a_collider(std::span<const Collider> before, std::span<const Collider> now,
                        const Vec3& from, const Vec3& to);

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
