/* A plugin as a binary built against an older ABI 1 header would be: symplectic Euler with
 * descriptor, integrator and parameter structs of their ABI 1.0 sizes. Compiled twice:
 * LEGACY_MINOR 0 uses only the 1.0 system callbacks (eval_acceleration, axpy); LEGACY_MINOR
 * 1 takes the step through the 1.1 step_rkn. The field where ABI 1.2 put get_extension
 * holds a function that aborts: a host that reads past struct_size crashes the test. */
#include <clothlab/plugin.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#ifndef LEGACY_MINOR
#error "define LEGACY_MINOR (0 or 1)"
#endif

static clothlab_status legacy_create(const clothlab_param_value* values, uint32_t value_count,
                                     void** out_instance, clothlab_message* error) {
  (void)values;
  if (value_count != 0 || out_instance == NULL) {
    snprintf(error->text, sizeof error->text, "expected no parameter values, got %u",
             (unsigned)value_count);
    return CLOTHLAB_ERROR_INVALID_ARGUMENT;
  }
  *out_instance = calloc(1, sizeof(void*)); /* holds the scratch vector */
  if (*out_instance == NULL) {
    snprintf(error->text, sizeof error->text, "out of memory");
    return CLOTHLAB_ERROR_OUT_OF_MEMORY;
  }
  return CLOTHLAB_OK;
}

#if LEGACY_MINOR >= 1
static const double zero[1] = {0.0}, one[1] = {1.0};
static const clothlab_rkn_scheme symplectic_euler = {
    sizeof(clothlab_rkn_scheme), 1, zero, zero, zero, zero, one, one};
#endif

static clothlab_status legacy_prepare(void* instance, const clothlab_system* system,
                                      clothlab_message* error) {
  if (system->struct_size < CLOTHLAB_SYSTEM_SIZE_1_0 ||
      (LEGACY_MINOR >= 1 && !CLOTHLAB_HAS_FIELD(system, clothlab_system, step_rkn))) {
    snprintf(error->text, sizeof error->text, "host system table too small (%u bytes)",
             (unsigned)system->struct_size);
    return CLOTHLAB_ERROR_UNSUPPORTED;
  }
#if LEGACY_MINOR >= 1
  {
    const clothlab_status status = system->reserve_rkn(system->context, 1);
    if (status != CLOTHLAB_OK) {
      snprintf(error->text, sizeof error->text, "reserve_rkn failed");
      return status;
    }
  }
#endif
  *(void**)instance = system->alloc_vector(system->context);
  if (*(void**)instance == NULL) {
    snprintf(error->text, sizeof error->text, "out of memory for scratch");
    return CLOTHLAB_ERROR_OUT_OF_MEMORY;
  }
  return CLOTHLAB_OK;
}

static clothlab_status legacy_step(void* instance, const clothlab_system* system, double t,
                                   double dt, clothlab_message* error) {
  clothlab_status status;
  if (!isfinite(dt) || dt < 0.0) {
    snprintf(error->text, sizeof error->text, "dt = %.17g: allowed finite >= 0", dt);
    return CLOTHLAB_ERROR_INVALID_ARGUMENT;
  }
  if (dt == 0.0) return CLOTHLAB_OK;
#if LEGACY_MINOR >= 1
  (void)instance;
  status = system->step_rkn(system->context, t, dt, &symplectic_euler);
#else
  status = system->eval_acceleration(system->context, t, system->x, system->v, *(void**)instance);
  if (status == CLOTHLAB_OK) {
    system->axpy(system->context, system->v, dt, *(void**)instance);
    system->axpy(system->context, system->x, dt, system->v);
  }
#endif
  if (status != CLOTHLAB_OK) snprintf(error->text, sizeof error->text, "step failed");
  return status;
}

static void legacy_destroy(void* instance) { free(instance); }

static const void* read_past_struct_size(const char* id) {
  (void)id;
  fprintf(stderr, "legacy_euler: the host called a field beyond struct_size\n");
  abort();
}

static const clothlab_integrator legacy_integrator = {
    CLOTHLAB_INTEGRATOR_SIZE_1_0,
    CLOTHLAB_INTEGRATOR_USES_VELOCITY_FORCES,
    LEGACY_MINOR ? "legacy-1-1" : "legacy-1-0",
    "Symplectic Euler built against an older ABI 1 header",
    "1.0.0",
    "v += dt a(x, v), then x += dt v, with 1.0-sized structs",
    1,
    1,
    (1u << CLOTHLAB_FLOAT32) | (1u << CLOTHLAB_FLOAT64),
    0,
    NULL,
    legacy_create,
    legacy_prepare,
    legacy_step,
    legacy_destroy,
    read_past_struct_size,
};

static const clothlab_integrator* const legacy_integrators[] = {&legacy_integrator};

static const clothlab_plugin_descriptor legacy_descriptor = {
    {CLOTHLAB_ABI_VERSION_MAJOR, LEGACY_MINOR},
    CLOTHLAB_DESCRIPTOR_SIZE_1_0,
    1,
    0,
    0,
    LEGACY_MINOR ? "clothlab-test-legacy-1-1" : "clothlab-test-legacy-1-0",
    "1.0.0",
    legacy_integrators,
    NULL};

CLOTHLAB_EXPORT const clothlab_plugin_descriptor* clothlab_plugin_entry(void) {
  return &legacy_descriptor;
}
