/*
 * Integrator extension "clothlab.solver-statistics/1": what an iterative or factorising
 * integrator (implicit Euler's CG, projective dynamics) did in its last step, so the host
 * can report iterations per step and count the steps whose solve missed its tolerance
 * instead of letting them pass silently.
 *
 * Integrator-side (the host pulls after each step) rather than a host extension the
 * plugin pushes into: any host that drives the plugin (the CLI, the conformance runner,
 * a test) reads the figures without offering anything, and a plugin needs no check
 * whether the host listens.
 *
 * Thread rule: as `step` (one host thread per instance at a time), called between steps.
 * Never allocates.
 */
#ifndef CLOTHLAB_EXT_SOLVER_STATISTICS_H
#define CLOTHLAB_EXT_SOLVER_STATISTICS_H

#include <clothlab/plugin.h>

#ifdef __cplusplus
extern "C" {
#endif

#define CLOTHLAB_EXT_SOLVER_STATISTICS "clothlab.solver-statistics/1"

/* The last step of one instance; all zero before the first step. */
typedef struct clothlab_solver_step_statistics {
  uint32_t struct_size;
  /* 1 when every solve of the step reached its tolerance, 0 when one stopped at its
   * iteration limit (or broke down) first. */
  uint32_t converged;
  /* Solver iterations in the step (CG iterations summed over Newton steps; local/global
   * iterations for projective dynamics). */
  uint64_t iterations;
  /* Matrix factorisations in the step (0 for matrix-free solvers). */
  uint64_t factorizations;
  /* The largest final residual of the step's solves, relative to its right-hand side. */
  double residual;
} clothlab_solver_step_statistics;

typedef struct clothlab_solver_statistics_extension {
  /* Fills *out (the caller sets out->struct_size) for `instance`'s last step. */
  clothlab_status (*last_step)(void *instance, clothlab_solver_step_statistics *out);
} clothlab_solver_statistics_extension;

#ifdef __cplusplus
}
#endif

#endif /* CLOTHLAB_EXT_SOLVER_STATISTICS_H */
