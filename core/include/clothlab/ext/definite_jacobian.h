/*
 * Host extension "clothlab.definite-jacobian/1": Baraff and Witkin's definite
 * approximation of the Jacobian of clothlab.jacobian/1, in one product, for implicit
 * integrators that solve with conjugate gradients at large steps.
 *
 * The linear map is D = c_x K + c_v (da/dv) at a state (x, v), with da/dv exact (as in
 * clothlab.jacobian/1; v NULL: no damping) and K the springs' part of da/dx without the
 * two terms that make the exact da/dx indefinite or unsymmetric: a spring of rest length
 * l0 and length l between particles i and j, direction n, adds
 *   (K u)_i += -(ks / m_i) S (u_i - u_j),   (K u)_j += -(ks / m_j) S (u_j - u_i),
 *   S = max(0, 1 - l0/l) (I - n n^T) + n n^T
 * (a compressed spring keeps no transverse stiffness), and no x-derivative of the damping
 * force. K has da/dx's sign (negative semi-definite in the mass inner product), so backward
 * Euler's matrix I - h^2 da/dx - h da/dv becomes I + D with c_x = -h^2, c_v = -h. M D is
 * symmetric; for c_x, c_v <= 0, I + D is positive definite in the mass inner product. Rows
 * and columns of pinned particles are zero.
 *
 * "clothlab.definite-jacobian/2" (ABI 1.3) is revision 1 with the block table: every 3x3
 * block of D at once, in the block pattern of clothlab.jacobian/1 (one pattern for both
 * forms, on a grid and on any mesh alike), so that a preconditioner assembles D without
 * probing it with products. The table is a CSR of blocks, not a per-spring list: a row's
 * blocks are what a multigrid level or an incomplete factor consumes, and two springs
 * joining the same pair share one block. Its values are double
 * whatever the precision: the diagonal blocks of I + D on a fine cloth carry a mass term below
 * single precision's resolution of the diagonal. A host offering /2 offers /1 too.
 *
 * Call `reserve` of clothlab.jacobian/1 from `prepare` first (it readies all). Thread
 * rule: as eval_acceleration. No allocation.
 */
#ifndef CLOTHLAB_EXT_DEFINITE_JACOBIAN_H
#define CLOTHLAB_EXT_DEFINITE_JACOBIAN_H

#include <clothlab/plugin.h>

#ifdef __cplusplus
extern "C" {
#endif

#define CLOTHLAB_EXT_DEFINITE_JACOBIAN "clothlab.definite-jacobian/1"
#define CLOTHLAB_EXT_DEFINITE_JACOBIAN_2 "clothlab.definite-jacobian/2"

typedef struct clothlab_definite_jacobian_extension {
  /* out = D u on active particles; out is 0 on pinned ones, u's pinned entries are
   * ignored. u and out are vectors of the system; out must not alias u, x or v. */
  clothlab_status (*apply)(void* context, double t, const void* x, const void* v, double c_x,
                           double c_v, const void* u, void* out);
  /* The 3x3 diagonal blocks of D: out[9 i + 3 r + c] = D_ii(r, c), n blocks, row-major,
   * double; pinned blocks are zero. out is caller-owned, 9 n doubles. */
  clothlab_status (*diagonal_blocks)(void* context, double t, const void* x, const void* v,
                                     double c_x, double c_v, double* out);
} clothlab_definite_jacobian_extension;

/* Revision 2: revision 1's calls, then the block table. */
typedef struct clothlab_definite_jacobian_2_extension {
  clothlab_status (*apply)(void* context, double t, const void* x, const void* v, double c_x,
                           double c_v, const void* u, void* out);
  clothlab_status (*diagonal_blocks)(void* context, double t, const void* x, const void* v,
                                     double c_x, double c_v, double* out);
  /* All blocks of D in the order of clothlab.jacobian/1's `pattern`: values[9 k + 3 r + c] for
   * block k, row-major, double; rows and columns of pinned particles are zero. values is
   * caller-owned, 9 block_count doubles. */
  clothlab_status (*blocks)(void* context, double t, const void* x, const void* v, double c_x,
                            double c_v, double* values);
} clothlab_definite_jacobian_2_extension;

#ifdef __cplusplus
}
#endif

#endif /* CLOTHLAB_EXT_DEFINITE_JACOBIAN_H */
