/*
 * Integrator extension "clothlab.integrator-traits/1": what the host and the
 * conformance runner may expect of an integrator beyond its descriptor. Static data.
 */
#ifndef CLOTHLAB_EXT_INTEGRATOR_TRAITS_H
#define CLOTHLAB_EXT_INTEGRATOR_TRAITS_H

#include <clothlab/plugin.h>

#ifdef __cplusplus
extern "C" {
#endif

#define CLOTHLAB_EXT_INTEGRATOR_TRAITS "clothlab.integrator-traits/1"

/* Stable at any step size on a damped cloth (implicit Euler, XPBD, projective
 * dynamics). "Stable" is the host's stability monitor's verdict (the one every clothlab run
 * gets, host/analysis stability_monitor.hpp): every coordinate finite, no structural spring
 * longer than 5 x its rest length, and the energy never above its initial value plus the work
 * the external forces can have done, plus a margin of the cloth's energy scale. The
 * conformance runner checks it after every step of 2 s at dt = 50 ms on the default sheet and
 * the default flag (stability.unconditional-*). Accuracy is not part of it: a stable step may
 * be far from the exact motion. Every integrator, declared or not, must also stay stable on
 * those scenes at the CLI's default dt (stability.default-*). */
#define CLOTHLAB_TRAIT_UNCONDITIONALLY_STABLE (1u << 0)
/* The result depends on an iteration count (parameter `iterations_param`): the order is
 * measured with iterations at its maximum, and the method is allowed to be inexact. */
#define CLOTHLAB_TRAIT_ITERATIVE (1u << 1)
/* Calls the host's clothlab.contacts/1 after each step or substep (ABI 1.3): the host runs
 * scenes with colliders (clothlab.colliders/1) only with integrators that declare it. */
#define CLOTHLAB_TRAIT_RESOLVES_CONTACTS (1u << 2)
/* Calls the host's clothlab.attachment-targets/1 once per step or substep (ABI 1.3), so the
 * attached particles follow their targets: the host runs scenes with attachments
 * (clothlab.attachments/1) only with integrators that declare it. */
#define CLOTHLAB_TRAIT_MOVES_ATTACHMENTS (1u << 3)
/* Solves locally: its iterations move one particle (or one constraint) at a time against its
 * neighbours' current positions, Gauss-Seidel or Jacobi sweeps of a position-based method
 * (XPBD, vertex block descent). Short of convergence a substep h then delivers a spring
 * stiffness of about m / h^2 at most (m: a particle's mass), so a cloth of warp/weft stiffness
 * ks behaves like itself only for h <~ sqrt(m / ks); `clothlab --choose` predicts the fewest
 * substeps per frame from that bound and reports it beside the ones it measures. */
#define CLOTHLAB_TRAIT_LOCAL_SOLVES (1u << 4)
/* Its step may apply a force of its own that does not come in pairs, such as a drag towards
 * world rest (verlet's `damping`): the free particles' momentum then changes by more than
 * gravity and the pins give it. The stability monitor measures the attachments' pull from that
 * momentum for every other integrator; for this one it samples the pull from the springs at the
 * pins. An integrator whose forces are the host's, its springs' and its constraints' between
 * particles (every other built-in) leaves it out; the conformance check numerics.momentum
 * holds it to that (a free cloth's momentum changes by gravity's impulse alone). */
#define CLOTHLAB_TRAIT_DRAGS_TOWARDS_REST (1u << 5)

typedef struct clothlab_integrator_traits {
  uint32_t struct_size;
  uint32_t flags; /* CLOTHLAB_TRAIT_* */
  /* Name of the parameter counting substeps per step ("substeps"), or NULL. */
  const char* substeps_param;
  /* Name of the parameter counting solver iterations ("iterations"), or NULL. */
  const char* iterations_param;
} clothlab_integrator_traits;

#ifdef __cplusplus
}
#endif

#endif /* CLOTHLAB_EXT_INTEGRATOR_TRAITS_H */
