/*
 * Host extension "clothlab.cg-step/1": the two sweeps of one iteration of block-Jacobi
 * preconditioned conjugate gradients on A = I + D, with D the definite Jacobian of
 * clothlab.definite-jacobian/1 (D = c_x K + c_v da/dv at a state (x, v)), in the mass inner
 * product <a, b> = sum over active particles of m_i a_i . b_i (kg times the vectors' units):
 *
 *   product: q = A p and <p, q>                               (the product's own sweep)
 *   update:  solution += alpha p, r -= alpha q, z = B r, <r, r> and <r, z>   (one sweep)
 *
 * B is the caller's preconditioner: one symmetric 3x3 block per particle, given as two
 * vectors of the system, `diagonal` (components B_00, B_11, B_22) and `off_diagonal`
 * (components B_01, B_02, B_12). A is dimensionless (c_x in s^2, c_v in s, as for
 * clothlab.definite-jacobian/1); alpha is the caller's step length.
 *
 * Same results as the separate calls (definite-jacobian apply, axpy, reductions mass_dot and
 * the block product) within rounding; the dot products are double, summed in a fixed order:
 * bitwise identical for any thread count. Only active particles are read or written: q and
 * z are 0 on pinned ones, p's pinned entries are ignored, the other vectors' pinned entries
 * are left as they are. Vectors must be distinct, except that update's blocks may be any
 * vectors the others are not.
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
  /* q = p + D p at (x, v) (v NULL: no damping), *p_dot_q = <p, q>. */
  clothlab_status (*product)(void* context, double t, const void* x, const void* v, double c_x,
                             double c_v, const void* p, void* q, double* p_dot_q);
  /* solution += alpha p, r -= alpha q, z = B r; *r_dot_r = <r, r>, *r_dot_z = <r, z> of the
   * updated r. */
  clothlab_status (*update)(void* context, double alpha, const void* p, const void* q,
                            const void* diagonal, const void* off_diagonal, void* solution, void* r,
                            void* z, double* r_dot_r, double* r_dot_z);
} clothlab_cg_step_extension;

#ifdef __cplusplus
}
#endif

#endif /* CLOTHLAB_EXT_CG_STEP_H */
