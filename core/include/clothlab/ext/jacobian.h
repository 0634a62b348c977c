/*
 * Host extension "clothlab.jacobian/1": derivatives of the acceleration a(t, x, v) =
 * M^-1 F(t, x, v) of eval_acceleration, for implicit integrators (Newton, Krylov) and
 * direct solvers.
 *
 * Every call takes the state (x, v) at which to linearise (vectors of the system, as for
 * eval_acceleration; v may be NULL for an integrator without velocity-dependent forces,
 * and then the damping terms are absent) and two weights c_x, c_v: the linear map is
 *   J = c_x (da/dx) + c_v (da/dv).
 * The derivatives are exact (analytic) for springs and their damping, and include the
 * x-dependence of the damping force. Wind's dependence on x is left out (its pressure on
 * the moving normals is treated as constant over a step): a(x) with wind differs from
 * its linearisation by that term. Rows and columns of pinned particles are zero.
 *
 * Thread rule: as eval_acceleration (one host thread per system at a time; the host may
 * use several threads inside). No allocation after `prepare`; `reserve` is the call
 * that may allocate and must come from `prepare`. The conformance runner enforces it
 * (robustness.no-alloc): after prepare its system refuses `reserve`, and refuses every call
 * here, of clothlab.definite-jacobian/1 and of clothlab.cg-step/1 when no `reserve` was made
 * in prepare, with CLOTHLAB_ERROR_INVALID_ARGUMENT and a failed check naming the call. (The
 * clothlab engine itself readies the Jacobian on first use, so a plugin that skips `reserve`
 * still runs there, allocating in its first step.)
 */
#ifndef CLOTHLAB_EXT_JACOBIAN_H
#define CLOTHLAB_EXT_JACOBIAN_H

#include <clothlab/plugin.h>

#ifdef __cplusplus
extern "C" {
#endif

#define CLOTHLAB_EXT_JACOBIAN "clothlab.jacobian/1"

/* The fixed block-sparse pattern of J: row i holds 3x3 blocks for the columns
 * columns[row_offsets[i] .. row_offsets[i + 1]), ascending, the diagonal included;
 * column j appears in row i iff a spring joins i and j (or i = j). Pinned rows are
 * present and zero. Host-owned, valid until the system is destroyed. */
typedef struct clothlab_block_pattern {
  uint32_t struct_size;
  uint32_t row_count;  /* n */
  uint32_t block_count; /* row_offsets[n] */
  uint32_t reserved0;
  const uint32_t *row_offsets; /* n + 1 */
  const uint32_t *columns;     /* block_count */
} clothlab_block_pattern;

typedef struct clothlab_jacobian_extension {
  /* During `prepare` only: readies the calls below (may allocate). */
  clothlab_status (*reserve)(void *context);
  /* out = J u on active particles; out is 0 on pinned ones, u's pinned entries are
   * ignored. u and out are vectors of the system; out must not alias u, x or v. */
  clothlab_status (*apply)(void *context, double t, const void *x, const void *v, double c_x,
                           double c_v, const void *u, void *out);
  /* The 3x3 diagonal blocks of J: out[9 i + 3 r + c] = J_ii(r, c), n blocks, row-major,
   * double whatever the precision; identity-free (pinned blocks are zero). For
   * block-Jacobi preconditioners. out is caller-owned, 9 n doubles. */
  clothlab_status (*diagonal_blocks)(void *context, double t, const void *x, const void *v,
                                     double c_x, double c_v, double *out);
  /* Fills *out with the pattern (the caller sets out->struct_size). */
  clothlab_status (*pattern)(void *context, clothlab_block_pattern *out);
  /* All blocks of J in the pattern's order: values[9 k + 3 r + c] for block k, row-major,
   * double. values is caller-owned, 9 block_count doubles. */
  clothlab_status (*blocks)(void *context, double t, const void *x, const void *v, double c_x,
                            double c_v, double *values);
} clothlab_jacobian_extension;

#ifdef __cplusplus
}
#endif

#endif /* CLOTHLAB_EXT_JACOBIAN_H */
