/*
 * A plugin in plain C99 against plugin.h alone: symplectic Euler with optional substeps.
 * It shows what the C++ SDK otherwise does for an author: validate parameters, report
 * errors in the message buffer, size scratch in prepare, never allocate in step.
 */
#include <clothlab/plugin.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

typedef struct c_euler {
  unsigned substeps;
  void* acceleration; /* host-owned scratch vector, from alloc_vector in prepare */
} c_euler;

static const clothlab_param_spec c_euler_params[] = {
    {sizeof(clothlab_param_spec),
     CLOTHLAB_PARAM_INT,
     "substeps",
     "Euler substeps per step (each of dt / substeps)",
     "",
     {1.0, 0.0, 0.0},
     1.0,
     16.0},
};

static clothlab_status c_euler_create(const clothlab_param_value* values, uint32_t value_count,
                                      void** out_instance, clothlab_message* error) {
  c_euler* instance;
  double substeps;
  if (value_count != 1 || values == NULL || out_instance == NULL) {
    snprintf(error->text, sizeof error->text, "expected 1 parameter value, got %u",
             (unsigned)value_count);
    return CLOTHLAB_ERROR_INVALID_ARGUMENT;
  }
  substeps = values[0].v[0];
  if (!(substeps >= 1.0 && substeps <= 16.0) || floor(substeps) != substeps) {
    snprintf(error->text, sizeof error->text,
             "parameter substeps = %.17g is outside [1, 16] or not an integer", substeps);
    return CLOTHLAB_ERROR_INVALID_ARGUMENT;
  }
  instance = (c_euler*)calloc(1, sizeof *instance);
  if (instance == NULL) {
    snprintf(error->text, sizeof error->text, "out of memory");
    return CLOTHLAB_ERROR_OUT_OF_MEMORY;
  }
  instance->substeps = (unsigned)substeps;
  *out_instance = instance;
  return CLOTHLAB_OK;
}

static clothlab_status c_euler_prepare(void* instance, const clothlab_system* system,
                                       clothlab_message* error) {
  c_euler* self = (c_euler*)instance;
  if (system->precision != CLOTHLAB_FLOAT32 && system->precision != CLOTHLAB_FLOAT64) {
    snprintf(error->text, sizeof error->text, "unknown precision %u", (unsigned)system->precision);
    return CLOTHLAB_ERROR_UNSUPPORTED;
  }
  self->acceleration = system->alloc_vector(system->context);
  if (self->acceleration == NULL) {
    snprintf(error->text, sizeof error->text, "out of memory for scratch");
    return CLOTHLAB_ERROR_OUT_OF_MEMORY;
  }
  return CLOTHLAB_OK;
}

/* Precision-independent: the host's vector callbacks do the arithmetic. */
static clothlab_status c_euler_step(void* instance, const clothlab_system* system, double t,
                                    double dt, clothlab_message* error) {
  c_euler* self = (c_euler*)instance;
  const double h = dt / self->substeps;
  unsigned i;
  if (!isfinite(dt) || dt < 0.0) {
    snprintf(error->text, sizeof error->text, "dt = %.17g: allowed finite >= 0", dt);
    return CLOTHLAB_ERROR_INVALID_ARGUMENT;
  }
  if (dt == 0.0) return CLOTHLAB_OK;
  for (i = 0; i < self->substeps; ++i) {
    const clothlab_status status = system->eval_acceleration(system->context, t + i * h, system->x,
                                                             system->v, self->acceleration);
    if (status != CLOTHLAB_OK) {
      snprintf(error->text, sizeof error->text, "acceleration evaluation failed (status %d)",
               (int)status);
      return status;
    }
    system->axpy(system->context, system->v, h, self->acceleration);
    system->axpy(system->context, system->x, h, system->v);
  }
  return CLOTHLAB_OK;
}

static void c_euler_destroy(void* instance) { free(instance); }

static const clothlab_integrator c_euler_integrator = {
    sizeof(clothlab_integrator),
    CLOTHLAB_INTEGRATOR_USES_VELOCITY_FORCES,
    "c-euler",
    "Symplectic Euler written in C",
    "1.0.0",
    "v += dt a(x, v), then x += dt v; first order; plain C99 against plugin.h",
    1,
    1,
    (1u << CLOTHLAB_FLOAT32) | (1u << CLOTHLAB_FLOAT64),
    1,
    c_euler_params,
    c_euler_create,
    c_euler_prepare,
    c_euler_step,
    c_euler_destroy,
    NULL, /* get_extension: no integrator extensions */
};

static const clothlab_integrator* const c_euler_integrators[] = {&c_euler_integrator};

static const clothlab_plugin_descriptor c_euler_descriptor = {
    {CLOTHLAB_ABI_VERSION_MAJOR, CLOTHLAB_ABI_VERSION_MINOR},
    sizeof(clothlab_plugin_descriptor),
    1,
    0,
    0,
    "c-euler",
    "1.0.0",
    c_euler_integrators,
    NULL,
};

const clothlab_plugin_descriptor* clothlab_plugin_entry(void) { return &c_euler_descriptor; }
