/*
 * ClothLab plugin ABI — the only contract between the host and a plugin library.
 *
 * Plain C (C99 and C++ compatible). Only C types cross the boundary: fixed-width
 * integers, double, pointers to arrays and `const char*`. Rules:
 *  - A library exports exactly one symbol, `clothlab_plugin_entry`, returning a
 *    descriptor whose first field is the ABI version it was built against. The host
 *    checks that version before reading anything else with clothlab_abi_is_compatible():
 *    a different major is refused, any minor of the same major is accepted.
 *  - Every struct carries `struct_size`; readers must not touch fields beyond it, and
 *    accept any size from the smallest published one (CLOTHLAB_*_SIZE_1_0 below) up.
 *    Minors 1.1 and 1.2 appended fields; since 1.2 the structs are frozen: the ABI grows
 *    by extensions, optional interfaces looked up by a versioned string id
 *    ("clothlab.jacobian/1") through `get_extension` on both sides, NULL when absent.
 *    1.3 appended the one field 1.2 left out, `get_extension` on clothlab_scenario, so
 *    scenarios grow by extensions too; no other struct changed.
 *    A new capability is a new id, a change of one is a new revision ("/2"); a published
 *    extension struct is never edited. One header per extension, in clothlab/ext/:
 *    host side topology, grid, jacobian, definite-jacobian, cg-step, reductions,
 *    external-forces, threads (the thread count a plugin's own parallel loops keep to),
 *    contacts (1.3);
 *    integrator side integrator-traits, explicit-scheme, solver-statistics;
 *    scenario side (1.3) colliders, air.
 *    Why a minor and not a new major: binaries built against 1.0 and 1.1 keep loading and
 *    give the same results, because every reader accepts the smaller struct sizes below;
 *    the only price is that the structs stop growing at 1.2 (the scenario at 1.3).
 *  - Errors are status codes plus a message written into a caller-owned buffer.
 *    No exception, longjmp or C++ type ever crosses the boundary.
 *  - Ownership: the host owns the cloth state and every vector of a clothlab_system;
 *    a plugin owns the instances it creates and frees them in `destroy`. Strings in
 *    descriptors and parameter specs are static: valid while the library is loaded.
 *  - Threads: every function is called from one host thread at a time per instance.
 *    Different instances may be used concurrently from different threads.
 */
#ifndef CLOTHLAB_PLUGIN_H
#define CLOTHLAB_PLUGIN_H

#include <stddef.h>
#include <stdint.h>

#define CLOTHLAB_ABI_VERSION_MAJOR 1u
#define CLOTHLAB_ABI_VERSION_MINOR 3u

#if defined(__GNUC__) || defined(__clang__)
#define CLOTHLAB_EXPORT __attribute__((visibility("default")))
#else
#define CLOTHLAB_EXPORT
#endif

#ifdef __cplusplus
extern "C" {
#endif

typedef struct clothlab_abi_version {
  uint32_t major;
  uint32_t minor;
} clothlab_abi_version;

/* ---------------------------------------------------------------- errors */

typedef int32_t clothlab_status;
#define CLOTHLAB_OK 0
#define CLOTHLAB_ERROR_INVALID_ARGUMENT 1 /* a parameter or input is out of range */
#define CLOTHLAB_ERROR_UNSUPPORTED 2      /* e.g. a precision the plugin lacks */
#define CLOTHLAB_ERROR_OUT_OF_MEMORY 3
#define CLOTHLAB_ERROR_NUMERICAL 4 /* the step produced or met a non-finite value */
#define CLOTHLAB_ERROR_INTERNAL 5  /* anything else, e.g. a caught exception */

#define CLOTHLAB_MESSAGE_CAPACITY 512
/* Caller-owned buffer; the callee writes a NUL-terminated one-line message when it
 * returns a status other than CLOTHLAB_OK. */
typedef struct clothlab_message {
  char text[CLOTHLAB_MESSAGE_CAPACITY];
} clothlab_message;

/* ------------------------------------------------------------ parameters */

#define CLOTHLAB_PARAM_REAL 1u /* double in [min, max] */
#define CLOTHLAB_PARAM_INT 2u  /* integer stored in a double, in [min, max] */
#define CLOTHLAB_PARAM_BOOL 3u /* 0 or 1 */
#define CLOTHLAB_PARAM_VEC3 4u /* three doubles, each in [min, max] */

/* Schema of one parameter. The host validates values against it before `create`;
 * plugins validate again and reject bad values with an error. */
typedef struct clothlab_param_spec {
  uint32_t struct_size;
  uint32_t type;            /* CLOTHLAB_PARAM_* */
  const char *name;         /* "structural.ks": [a-z0-9_.]+, unique per component */
  const char *help;         /* one line */
  const char *unit;         /* "N/m", "kg", "" */
  double default_value[3];  /* VEC3 uses all three; other types use [0] */
  double min_value;         /* inclusive; per component for VEC3 */
  double max_value;         /* inclusive */
} clothlab_param_spec;

/* One value per spec, in spec order. Scalars use v[0]. */
typedef struct clothlab_param_value {
  double v[3];
} clothlab_param_value;

/* ---------------------------------------------------------------- system */

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
  const void *base;
  uint32_t count; /* 0 .. CLOTHLAB_COMBINATION_MAX_TERMS */
  uint32_t reserved0;
  const double *coefficients;
  const void *const *vectors;
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
  uint32_t stages; /* 1 .. CLOTHLAB_RKN_MAX_STAGES */
  const double *c;          /* stages */
  const double *alpha;      /* stages */
  const double *x_coupling; /* stages x stages, row-major */
  const double *v_coupling; /* stages x stages, row-major */
  const double *x_weights;  /* stages */
  const double *v_weights;  /* stages */
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
  uint32_t precision;      /* CLOTHLAB_FLOAT32 or CLOTHLAB_FLOAT64 */
  uint32_t particle_count; /* n */
  uint32_t stride;         /* >= n, multiple of 16 */
  void *x;                 /* positions at the current time (in/out) */
  void *v;                 /* velocities at the current time (in/out) */
  const void *inverse_mass;     /* n elements; 0 for pinned particles */
  const clothlab_range *active; /* unpinned particles, ascending, disjoint */
  uint32_t active_count;
  uint32_t reserved0;
  void *context;

  /* a = M^-1 F(t, x, v) on active particles; a is left at 0 for pinned ones.
   * v may be NULL only for an integrator without CLOTHLAB_INTEGRATOR_USES_VELOCITY_FORCES
   * (the host then builds no damping stage). Returns CLOTHLAB_ERROR_NUMERICAL if the
   * result is not finite. */
  clothlab_status (*eval_acceleration)(void *context, double t, const void *x,
                                       const void *v, void *a);
  /* y += alpha * x, on active particles. */
  void (*axpy)(void *context, void *y, double alpha, const void *x);
  /* out = base + sum_i coefficients[i] * vectors[i], on active particles.
   * out may alias base or any vector. */
  void (*lincomb)(void *context, void *out, const void *base, uint32_t count,
                  const double *coefficients, const void *const *vectors);
  /* dst = src on every particle, pinned included. */
  void (*copy)(void *context, void *dst, const void *src);
  /* A zeroed vector owned by the host, freed with the system. Only during `prepare`;
   * returns NULL when out of memory. (Like reserve_rkn and clothlab.jacobian/1's reserve,
   * the conformance runner refuses it after prepare: robustness.no-alloc.) */
  void *(*alloc_vector)(void *context);

  /* ---- since 1.1: present when struct_size covers it ---- */

  /* eval_acceleration at the state x = x->base + sum ..., v = v->base + sum ..., each
   * formed row by row inside the force pass and never stored: a Runge-Kutta stage costs
   * one pass over memory instead of a lincomb per stage vector and an evaluation.
   * Pinned particles take the base values. v may be NULL as for eval_acceleration; a
   * count above CLOTHLAB_COMBINATION_MAX_TERMS is CLOTHLAB_ERROR_INVALID_ARGUMENT. */
  clothlab_status (*eval_acceleration_at)(void *context, double t, const clothlab_combination *x,
                                          const clothlab_combination *v, void *a);
  /* During `prepare` only: readies step_rkn for schemes of up to `stages` stages (may
   * allocate). CLOTHLAB_ERROR_INVALID_ARGUMENT above CLOTHLAB_RKN_MAX_STAGES. */
  clothlab_status (*reserve_rkn)(void *context, uint32_t stages);
  /* One step t -> t + h of an explicit Runge-Kutta-Nystrom scheme on x and v, which the
   * host may run as one fused sweep over memory (stage states and accelerations never
   * stored as vectors). Pinned particles stay put. Needs reserve_rkn with at least
   * scheme->stages; CLOTHLAB_ERROR_NUMERICAL when a stage acceleration is not finite
   * (x and v are then partly advanced). */
  clothlab_status (*step_rkn)(void *context, double t, double h,
                              const clothlab_rkn_scheme *scheme);

  /* ---- since 1.2: present when struct_size covers it; the last field ever added ---- */

  /* The host extension with this id ("clothlab.topology/1", ...), or NULL when the host
   * does not offer it (unknown id, other revision, NULL id). The returned struct is
   * static: valid while the host library is loaded. Any thread, any time. */
  const void *(*get_extension)(void *context, const char *id);
} clothlab_system;

/* ------------------------------------------------------------ integrator */

/* The integrator evaluates damping (velocity-dependent) forces: without this flag the
 * host passes v = NULL to eval_acceleration and skips damping terms entirely. */
#define CLOTHLAB_INTEGRATOR_USES_VELOCITY_FORCES (1u << 0)

typedef struct clothlab_integrator {
  uint32_t struct_size;
  uint32_t flags;          /* CLOTHLAB_INTEGRATOR_* */
  const char *id;          /* "rk4": [a-z0-9_-]+, unique within the library */
  const char *name;        /* "Classic Runge-Kutta (RK4)" */
  const char *version;     /* "1.0.0" */
  const char *description; /* one line */
  uint32_t order;          /* declared order of global accuracy in dt */
  uint32_t evals_per_step; /* eval_acceleration calls per step (for cost accounting) */
  uint32_t precisions;     /* bit mask of (1 << CLOTHLAB_FLOAT32) | (1 << CLOTHLAB_FLOAT64) */
  uint32_t param_count;
  const clothlab_param_spec *params;

  /* Creates an instance from validated values (one per spec). May allocate. Must not
   * call back into the host. */
  clothlab_status (*create)(const clothlab_param_value *values, uint32_t value_count,
                            void **out_instance, clothlab_message *error);
  /* Binds the instance to a system before its first step: sizes scratch with
   * system->alloc_vector, resets history. May be called again to rebind. */
  clothlab_status (*prepare)(void *instance, const clothlab_system *system,
                             clothlab_message *error);
  /* Advances system->x and system->v from t to t + dt. Must not allocate, in the calling
   * thread or in any thread of the plugin's own (the conformance runner counts allocator calls
   * of every thread during step). dt = 0 leaves the state unchanged. */
  clothlab_status (*step)(void *instance, const clothlab_system *system, double t, double dt,
                          clothlab_message *error);
  void (*destroy)(void *instance);

  /* ---- since 1.2: present when struct_size covers it; the last field ever added ---- */

  /* The integrator extension with this id ("clothlab.integrator-traits/1", ...), or
   * NULL. May be NULL itself (no extensions). Returns static data; any thread, any time,
   * without an instance. */
  const void *(*get_extension)(const char *id);
} clothlab_integrator;

/* -------------------------------------------------------------- scenario */

typedef struct clothlab_spring_family {
  double ks; /* Hooke stiffness, N/m */
  double kd; /* linear damping along the spring, N s/m */
} clothlab_spring_family;

/*
 * A regular grid cloth: particle (r, c), index r * cols + c, starts at
 *   origin + c * (width / (cols - 1)) * col_axis + r * (height / (rows - 1)) * row_axis
 * (a 1-wide dimension puts every particle at offset 0 along it). Springs are the Provot
 * stencils, rest lengths taken from this initial layout: structural (0,1),(1,0);
 * shear (1,1),(1,-1); flexion (0,2),(2,0). Mass is spread evenly; pinned particles get
 * inverse mass 0. Wind acts on each grid triangle as a pressure along its normal:
 * F = wind_strength * area * (n . wind_direction) n, shared equally by its 3 corners.
 */
typedef struct clothlab_scene {
  uint32_t struct_size;
  uint32_t rows;
  uint32_t cols;
  uint32_t pinned_count;
  const uint32_t *pinned; /* particle indices; valid until the instance is destroyed */
  double width;           /* metres along col_axis */
  double height;          /* metres along row_axis */
  double origin[3];
  double col_axis[3]; /* unit */
  double row_axis[3]; /* unit */
  double total_mass;  /* kg */
  clothlab_spring_family structural;
  clothlab_spring_family shear;
  clothlab_spring_family flexion;
  double gravity[3];        /* m/s^2 */
  double wind_direction[3]; /* unit; ignored when wind_strength is 0 */
  double wind_strength;     /* N/m^2; 0 = no wind stage at all */
} clothlab_scene;

typedef struct clothlab_scenario {
  uint32_t struct_size;
  uint32_t reserved0;
  const char *id;          /* "flag" */
  const char *name;        /* "Flag in wind" */
  const char *version;     /* "1.0.0" */
  const char *description; /* one line */
  uint32_t param_count;
  uint32_t reserved1;
  const clothlab_param_spec *params;

  clothlab_status (*create)(const clothlab_param_value *values, uint32_t value_count,
                            void **out_instance, clothlab_message *error);
  /* Fills *scene. The host sets scene->struct_size before the call. */
  clothlab_status (*describe)(void *instance, clothlab_scene *scene, clothlab_message *error);
  void (*destroy)(void *instance);

  /* ---- since 1.3: present when struct_size covers it; the last field ever added ---- */

  /* The scenario extension with this id, or NULL. May be NULL itself (no extensions).
   * Returns static data; any thread, any time, without an instance. Tables whose
   * functions concern one scene take the instance `create` made as their first argument. */
  const void *(*get_extension)(const char *id);
} clothlab_scenario;

/* ------------------------------------------------------------------ entry */

/* A library may hold several integrators and scenarios. The clothlab CLI loads the file an
 * --integrator / --scenario argument names (NAME: NAME.so on the plugin search path) and
 * takes its only integrator (scenario), or else the one whose id equals the file name
 * without ".so"; a library with several and none of that id is refused, listing the ids it
 * holds. So a library of several integrators is installed once per id that should be
 * runnable, as <id>.so (a copy or a symbolic link). `clothlab --list-plugins` lists every
 * id of every library. */
typedef struct clothlab_plugin_descriptor {
  clothlab_abi_version abi_version; /* first, always: checked before anything else */
  uint32_t struct_size;
  uint32_t integrator_count;
  uint32_t scenario_count;
  uint32_t reserved0;
  const char *library_name;    /* "clothlab-builtin-rk4" */
  const char *library_version; /* "1.0.0" */
  const clothlab_integrator *const *integrators;
  const clothlab_scenario *const *scenarios;
} clothlab_plugin_descriptor;

#define CLOTHLAB_PLUGIN_ENTRY_SYMBOL "clothlab_plugin_entry"
typedef const clothlab_plugin_descriptor *(*clothlab_plugin_entry_fn)(void);

/* The one symbol a plugin library exports. Returns a pointer to static data. */
CLOTHLAB_EXPORT const clothlab_plugin_descriptor *clothlab_plugin_entry(void);

/* ------------------------------------------------------------ compatibility */

/* The one compatibility rule, used by the host's loader, the SDK and the conformance
 * runner: same major, any minor. */
static inline int clothlab_abi_is_compatible(clothlab_abi_version plugin_version) {
  return plugin_version.major == CLOTHLAB_ABI_VERSION_MAJOR;
}

/* Smallest struct_size of each struct in each published version. A reader accepts any
 * struct_size >= the 1.0 size and reads a field only when CLOTHLAB_HAS_FIELD says so. */
#define CLOTHLAB_FIELD_END(type, field) (offsetof(type, field) + sizeof(((type *)0)->field))
#define CLOTHLAB_HAS_FIELD(pointer, type, field) \
  ((size_t)(pointer)->struct_size >= CLOTHLAB_FIELD_END(type, field))

#define CLOTHLAB_DESCRIPTOR_SIZE_1_0 CLOTHLAB_FIELD_END(clothlab_plugin_descriptor, scenarios)
#define CLOTHLAB_INTEGRATOR_SIZE_1_0 CLOTHLAB_FIELD_END(clothlab_integrator, destroy)
#define CLOTHLAB_INTEGRATOR_SIZE_1_2 CLOTHLAB_FIELD_END(clothlab_integrator, get_extension)
#define CLOTHLAB_SCENARIO_SIZE_1_0 CLOTHLAB_FIELD_END(clothlab_scenario, destroy)
#define CLOTHLAB_SCENARIO_SIZE_1_3 CLOTHLAB_FIELD_END(clothlab_scenario, get_extension)
#define CLOTHLAB_SCENE_SIZE_1_0 CLOTHLAB_FIELD_END(clothlab_scene, wind_strength)
#define CLOTHLAB_PARAM_SPEC_SIZE_1_0 CLOTHLAB_FIELD_END(clothlab_param_spec, max_value)
#define CLOTHLAB_SYSTEM_SIZE_1_0 CLOTHLAB_FIELD_END(clothlab_system, alloc_vector)
#define CLOTHLAB_SYSTEM_SIZE_1_1 CLOTHLAB_FIELD_END(clothlab_system, step_rkn)
#define CLOTHLAB_SYSTEM_SIZE_1_2 CLOTHLAB_FIELD_END(clothlab_system, get_extension)

/* The one safe way to look an extension up: NULL when the struct predates 1.2 (1.3 for a
 * scenario: its get_extension field is not there to read), when the field is NULL, or when
 * the other side does not offer `id`. */
static inline const void *clothlab_system_extension(const clothlab_system *system,
                                                    const char *id) {
  if (!CLOTHLAB_HAS_FIELD(system, clothlab_system, get_extension) || !system->get_extension)
    return NULL;
  return system->get_extension(system->context, id);
}
static inline const void *clothlab_integrator_extension(const clothlab_integrator *integrator,
                                                        const char *id) {
  if (!CLOTHLAB_HAS_FIELD(integrator, clothlab_integrator, get_extension) ||
      !integrator->get_extension)
    return NULL;
  return integrator->get_extension(id);
}
static inline const void *clothlab_scenario_extension(const clothlab_scenario *scenario,
                                                      const char *id) {
  if (!CLOTHLAB_HAS_FIELD(scenario, clothlab_scenario, get_extension) || !scenario->get_extension)
    return NULL;
  return scenario->get_extension(id);
}

#ifdef __cplusplus
}
#endif

#endif /* CLOTHLAB_PLUGIN_H */
