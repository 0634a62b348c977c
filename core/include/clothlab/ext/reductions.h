/*
 * Host extension "clothlab.reductions/1": reductions over the active (unpinned)
 * particles of a system's vectors, for Krylov solvers and convergence tests. Results
 * are double whatever the precision, summed in a fixed order: bitwise identical for any
 * thread count. Thread rule: as eval_acceleration. Never allocates.
 */
#ifndef CLOTHLAB_EXT_REDUCTIONS_H
#define CLOTHLAB_EXT_REDUCTIONS_H

#include <clothlab/plugin.h>

#ifdef __cplusplus
extern "C" {
#endif

#define CLOTHLAB_EXT_REDUCTIONS "clothlab.reductions/1"

typedef struct clothlab_reductions_extension {
  /* sum over active particles and components of a * b. */
  double (*dot)(void *context, const void *a, const void *b);
  /* sum over active particles and components of w_i a * b, with w_i the particle's mass
   * (1 / inverse_mass): the M-inner product. */
  double (*mass_dot)(void *context, const void *a, const void *b);
  /* max over active particles and components of |a|. */
  double (*max_abs)(void *context, const void *a);
} clothlab_reductions_extension;

#ifdef __cplusplus
}
#endif

#endif /* CLOTHLAB_EXT_REDUCTIONS_H */
