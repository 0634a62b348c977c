/*
 * ClothLab plugin ABI: the cloth as an integrator sees it, a host-owned first-order system with
 * host callbacks (force evaluation, vector operations, the fused Runge-Kutta-Nystrom step) and
 * the host's extensions. The host owns the state and every vector of a system.
 */
#ifndef CLOTHLAB_ABI_SYSTEM_H
#define CLOTHLAB_ABI_SYSTEM_H

#include <clothlab/abi/status.h>
#include <clothlab/abi/version.h>

#ifdef __cplusplus
extern "C" {
#endif

#define CLOTHLAB_FLOAT32 1u
#define CLOTHLAB_FLOAT64 2u

/* Half-open range [begin, end) of particle indices. */
typedef struct clothlab_range {
  uint32_t begin;
  uint32_t end;
} clothlab_range;

/* base + sum_i coefficients[i] * vectors[i] over vectors of a system (since 1.1). */
#define CLOTHLAB_COMBINATION_MAX_TERMS 8u
typedef struct clothlab_combination {
  const void* base;
  uint32_t count; /* 0 .. CLOTHLAB_COMBINATION_MAX_TERMS */
  uint32_t reserved0;
  const double* coefficients;
  const void* const* vectors;
} clothlab_combination;

/* An explicit Runge-Kutta-Nystrom scheme for x'' = a(t, x, x') (since 1.1): stage i of s,
 *   X_i = x + h alpha[i] v + h^2 sum_{j<i} x_coupling[i s + j] A_j,
 *   V_i = v + h sum_{j<i} v_coupling[i s + j] A_j,     A_i = a(t + c[i] h, X_i, V_i),
 * then x += h v + h^2 sum_i x_weights[i] A_i,  v += h sum_i v_weights[i] A_i.
 * Any explicit Runge-Kutta method applied to (x, v) has this form (x_coupling = A^2,
 * x_weights = b A); so do symplectic Euler (one stage, weights 1) and other splittings.
 * Entries on and above the coupling diagonals are ignored. */
#define CLOTHLAB_RKN_MAX_STAGES 8u
typedef struct clothlab_rkn_scheme {
  uint32_t struct_size;
  uint32_t stages;          /* 1 .. CLOTHLAB_RKN_MAX_STAGES */
  const double* c;          /* stages */
  const double* alpha;      /* stages */
  const double* x_coupling; /* stages x stages, row-major */
  const double* v_coupling; /* stages x stages, row-major */
  const double* x_weights;  /* stages */
  const double* v_weights;  /* stages */
} clothlab_rkn_scheme;

/*
 * The cloth as an integrator sees it: the first-order system
 *   dx/dt = v,  dv/dt = a(t, x, v) = M^-1 F(t, x, v).
 *
 * A "vector" is one host-owned array of 3 * stride elements of the system's precision
 * (float for CLOTHLAB_FLOAT32, double for CLOTHLAB_FLOAT64): x components in
 * [0, n), y in [stride, stride + n), z in [2 stride, 2 stride + n). Arrays are 64-byte
 * aligned. Pinned particles (inverse mass 0) lie outside every active range; integrators
 * must leave their x and v untouched. All callbacks are owned by the host, receive
 * `context`, may use several threads internally and never allocate.
 *
 * Force evaluations (the run summary's force_evals): each call of eval_acceleration or
 * eval_acceleration_at counts one, step_rkn counts its stages. The extensions' calls do not
 * count: external forces alone (clothlab.external-forces/1), Jacobian and definite-Jacobian
 * products and cg-step sweeps (an XPBD run, which uses only external forces, reports 0).
 */
typedef struct clothlab_system {
  uint32_t struct_size;
  uint32_t precision;           /* CLOTHLAB_FLOAT32 or CLOTHLAB_FLOAT64 */
  uint32_t particle_count;      /* n */
  uint32_t stride;              /* >= n, multiple of 16 */
  void* x;                      /* positions at the current time (in/out) */
  void* v;                      /* velocities at the current time (in/out) */
  const void* inverse_mass;     /* n elements; 0 for pinned particles */
  const clothlab_range* active; /* unpinned particles, ascending, disjoint */
  uint32_t active_count;
  uint32_t reserved0;
  void* context;

  /* a = M^-1 F(t, x, v) on active particles; a is left at 0 for pinned ones.
   * v may be NULL only for an integrator without CLOTHLAB_INTEGRATOR_USES_VELOCITY_FORCES
   * (the host then builds no damping stage). Returns CLOTHLAB_ERROR_NUMERICAL if the
   * result is not finite. */
  clothlab_status (*eval_acceleration)(void* context, double t, const void* x, const void* v,
                                       void* a);
  /* y += alpha * x, on active particles. */
  void (*axpy)(void* context, void* y, double alpha, const void* x);
  /* out = base + sum_i coefficients[i] * vectors[i], on active particles.
   * out may alias base or any vector. */
  void (*lincomb)(void* context, void* out, const void* base, uint32_t count,
                  const double* coefficients, const void* const* vectors);
  /* dst = src on every particle, pinned included. */
  void (*copy)(void* context, void* dst, const void* src);
  /* A zeroed vector owned by the host, freed with the system. Only during `prepare`;
   * returns NULL when out of memory. (Like reserve_rkn and clothlab.jacobian/1's reserve,
   * the conformance runner refuses it after prepare: robustness.no-alloc.) */
  void* (*alloc_vector)(void* context);

  /* ---- since 1.1: present when struct_size covers it ---- */

  /* eval_acceleration at the state x = x->base + sum ..., v = v->base + sum ..., each
   * formed row by row inside the force pass and never stored: a Runge-Kutta stage costs
   * one pass over memory instead of a lincomb per stage vector and an evaluation.
   * Pinned particles take the base values. v may be NULL as for eval_acceleration; a
   * count above CLOTHLAB_COMBINATION_MAX_TERMS is CLOTHLAB_ERROR_INVALID_ARGUMENT. */
  clothlab_status (*eval_acceleration_at)(void* context, double t, const clothlab_combination* x,
                                          const clothlab_combination* v, void* a);
  /* During `prepare` only: readies step_rkn for schemes of up to `stages` stages (may
   * allocate). CLOTHLAB_ERROR_INVALID_ARGUMENT above CLOTHLAB_RKN_MAX_STAGES. */
  clothlab_status (*reserve_rkn)(void* context, uint32_t stages);
  /* One step t -> t + h of an explicit Runge-Kutta-Nystrom scheme on x and v, which the
   * host may run as one fused sweep over memory (stage states and accelerations never
   * stored as vectors). Pinned particles stay put. Needs reserve_rkn with at least
   * scheme->stages; CLOTHLAB_ERROR_NUMERICAL when a stage acceleration is not finite
   * (x and v are then partly advanced). */
  clothlab_status (*step_rkn)(void* context, double t, double h, const clothlab_rkn_scheme* scheme);

  /* ---- since 1.2: present when struct_size covers it; the last field ever added ---- */

  /* The host extension with this id ("clothlab.topology/1", ...), or NULL when the host
   * does not offer it (unknown id, other revision, NULL id). The returned struct is
   * static: valid while the host library is loaded. Any thread, any time. */
  const void* (*get_extension)(void* context, const char* id);
} clothlab_system;

#define CLOTHLAB_SYSTEM_SIZE_1_0 CLOTHLAB_FIELD_END(clothlab_system, alloc_vector)
#define CLOTHLAB_SYSTEM_SIZE_1_1 CLOTHLAB_FIELD_END(clothlab_system, step_rkn)
#define CLOTHLAB_SYSTEM_SIZE_1_2 CLOTHLAB_FIELD_END(clothlab_system, get_extension)

/* The one safe way to look an extension up: NULL when the struct predates the field (1.2 for a
 * system or an integrator, 1.3 for a scenario), when the field is NULL, or when the other side
 * does not offer `id`. */
static inline const void* clothlab_system_extension(const clothlab_system* system, const char* id) {
  if (!CLOTHLAB_HAS_FIELD(system, clothlab_system, get_extension) || !system->get_extension)
    return NULL;
  return system->get_extension(system->context, id);
}

#ifdef __cplusplus
}
#endif

#endif /* CLOTHLAB_ABI_SYSTEM_H */
