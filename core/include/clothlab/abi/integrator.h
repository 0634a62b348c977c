/*
 * ClothLab plugin ABI: an integrator's descriptor, its lifecycle (create, prepare, step,
 * destroy) and its extensions. A plugin owns the instances it creates and frees them in
 * `destroy`; every function is called from one host thread at a time per instance.
 */
#ifndef CLOTHLAB_ABI_INTEGRATOR_H
#define CLOTHLAB_ABI_INTEGRATOR_H

#include <clothlab/abi/params.h>
#include <clothlab/abi/status.h>
#include <clothlab/abi/system.h>
#include <clothlab/abi/version.h>

#ifdef __cplusplus
extern "C" {
#endif

/* The integrator evaluates damping (velocity-dependent) forces: without this flag the
 * host passes v = NULL to eval_acceleration and skips damping terms entirely. */
#define CLOTHLAB_INTEGRATOR_USES_VELOCITY_FORCES (1u << 0)

typedef struct clothlab_integrator {
  uint32_t struct_size;
  uint32_t flags;          /* CLOTHLAB_INTEGRATOR_* */
  const char* id;          /* "rk4": [a-z0-9_-]+, unique within the library */
  const char* name;        /* "Classic Runge-Kutta (RK4)" */
  const char* version;     /* "1.0.0" */
  const char* description; /* one line */
  uint32_t order;          /* declared order of global accuracy in dt */
  uint32_t evals_per_step; /* eval_acceleration calls per step (for cost accounting) */
  uint32_t precisions;     /* bit mask of (1 << CLOTHLAB_FLOAT32) | (1 << CLOTHLAB_FLOAT64) */
  uint32_t param_count;
  const clothlab_param_spec* params;

  /* Creates an instance from validated values (one per spec). May allocate. Must not
   * call back into the host. */
  clothlab_status (*create)(const clothlab_param_value* values, uint32_t value_count,
                            void** out_instance, clothlab_message* error);
  /* Binds the instance to a system before its first step: sizes scratch with
   * system->alloc_vector, resets history. May be called again to rebind. */
  clothlab_status (*prepare)(void* instance, const clothlab_system* system,
                             clothlab_message* error);
  /* Advances system->x and system->v from t to t + dt. Must not allocate, in the calling
   * thread or in any thread of the plugin's own (the conformance runner counts allocator calls
   * of every thread during step). dt = 0 leaves the state unchanged. */
  clothlab_status (*step)(void* instance, const clothlab_system* system, double t, double dt,
                          clothlab_message* error);
  void (*destroy)(void* instance);

  /* ---- since 1.2: present when struct_size covers it; the last field ever added ---- */

  /* The integrator extension with this id ("clothlab.integrator-traits/1", ...), or
   * NULL. May be NULL itself (no extensions). Returns static data; any thread, any time,
   * without an instance. */
  const void* (*get_extension)(const char* id);
} clothlab_integrator;

#define CLOTHLAB_INTEGRATOR_SIZE_1_0 CLOTHLAB_FIELD_END(clothlab_integrator, destroy)
#define CLOTHLAB_INTEGRATOR_SIZE_1_2 CLOTHLAB_FIELD_END(clothlab_integrator, get_extension)

/* The one safe way to look an extension up: NULL when the struct predates the field (1.2 for a
 * system or an integrator, 1.3 for a scenario), when the field is NULL, or when the other side
 * does not offer `id`. */
static inline const void* clothlab_integrator_extension(const clothlab_integrator* integrator,
                                                        const char* id) {
  if (!CLOTHLAB_HAS_FIELD(integrator, clothlab_integrator, get_extension) ||
      !integrator->get_extension)
    return NULL;
  return integrator->get_extension(id);
}

#ifdef __cplusplus
}
#endif

#endif /* CLOTHLAB_ABI_INTEGRATOR_H */
