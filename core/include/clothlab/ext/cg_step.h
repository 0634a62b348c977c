/*
 * Host extension "clothlab.cg-step/1": the two sweeps of one iteration of block-Jacobi
 * preconditioned conjugate gradients on A = I + D, with D the definite Jacobian of
 * clothlab.definite-jacobian/1 (D = c_x K + c_v da/dv at a state (x, v)), in the mass inner
 * product <a, b> = sum over active particles of m_i a_i . b_i (kg times the vectors' units):
 *
 *   linearise: A at the state, once per solve (per-spring coefficients, host-owned)
 *   product:   solution += alpha p, p = z + beta p (the last iteration's direction, optional),
 *              then q = A p and <p, q>                          (one sweep: the product's)
 *   update:    r -= alpha q, z = B r, <r, r> and <r, z>         (one sweep)
 *
 * The solution's and the direction's updates ride on the product's sweep, which reads p
 * anyway; after the last update the caller adds alpha p to the solution itself (axpy). B is the
 * caller's preconditioner: one symmetric 3x3 block per particle, given as two vectors of the
 * system, `diagonal` (components B_00, B_11, B_22) and `off_diagonal` (components B_01, B_02,
 * B_12). A is dimensionless (c_x in s^2, c_v in s, as for clothlab.definite-jacobian/1); alpha
 * and beta are the caller's CG coefficients.
 *
 * Same results as the separate calls (definite-jacobian apply, axpy, lincomb, reductions
 * mass_dot and the block product) within rounding; the dot products are double, summed in a
 * fixed order: bitwise identical for any thread count. Only active particles are written: q is
 * 0 on pinned ones and product ignores p's pinned entries; the other vectors' pinned entries
 * are left as they are. The vectors of one call must be distinct.
 *
 * Lifetime: the table is static; its calls need clothlab.jacobian/1's `reserve` made first
 * (from `prepare`). Thread rule: as eval_acceleration. Never allocates.
 */
#ifndef CLOTHLAB_EXT_CG_STEP_H
#define CLOTHLAB_EXT_CG_STEP_H

#include <clothlab/plugin.h>

#ifdef __cplusplus
extern "C" {
#endif

#define CLOTHLAB_EXT_CG_STEP "clothlab.cg-step/1"

typedef struct clothlab_cg_step_extension {
  /* Fixes A at (x, v) (v NULL: no damping) with weights c_x, c_v for the products that follow,
   * until the next call. x and v are read again by each product: their values must not change
   * meanwhile. Costs about one product. */
  clothlab_status (*linearise)(void* context, double t, const void* x, const void* v, double c_x,
                               double c_v);
  /* With z not NULL, first solution += alpha p, then p = z + beta p (z NULL: p, solution and
   * the coefficients are left alone); then q = A p = p + D p, *p_dot_q = <p, q>.
   * CLOTHLAB_ERROR_INVALID_ARGUMENT before any linearise. */
  clothlab_status (*product)(void* context, double alpha, double beta, const void* z, void* p,
                             void* solution, void* q, double* p_dot_q);
  /* r -= alpha q, z = B r; *r_dot_r = <r, r>, *r_dot_z = <r, z> of the updated r. */
  clothlab_status (*update)(void* context, double alpha, const void* q, const void* diagonal,
                            const void* off_diagonal, void* r, void* z, double* r_dot_r,
                            double* r_dot_z);
} clothlab_cg_step_extension;

#ifdef __cplusplus
}
#endif

#endif /* CLOTHLAB_EXT_CG_STEP_H */
