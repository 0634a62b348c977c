/* A scenario as a binary built against the ABI 1.2 header would be: its clothlab_scenario
 * ends at `destroy` (struct_size 1.0 = 1.2). The field where ABI 1.3 put get_extension holds
 * a function that aborts: a host that reads past struct_size crashes the test. */
#include <clothlab/plugin.h>
#include <stdio.h>
#include <stdlib.h>

static int instance_marker;

static clothlab_status create(const clothlab_param_value* values, uint32_t value_count,
                              void** out_instance, clothlab_message* error) {
  (void)values;
  (void)error;
  if (value_count != 0 || out_instance == NULL) return CLOTHLAB_ERROR_INVALID_ARGUMENT;
  *out_instance = &instance_marker;
  return CLOTHLAB_OK;
}

/* Two particles one metre apart along x, the first pinned. */
static const uint32_t pinned[] = {0};
static clothlab_status describe(void* instance, clothlab_scene* scene, clothlab_message* error) {
  (void)instance;
  (void)error;
  scene->rows = 1;
  scene->cols = 2;
  scene->pinned_count = 1;
  scene->pinned = pinned;
  scene->width = 1.0;
  scene->height = 1.0;
  scene->col_axis[0] = 1.0;
  scene->row_axis[1] = -1.0;
  scene->total_mass = 0.1;
  scene->structural.ks = 10.0;
  scene->gravity[1] = -9.81;
  return CLOTHLAB_OK;
}

static void destroy(void* instance) { (void)instance; }

static const void* read_past_struct_size(const char* id) {
  (void)id;
  fprintf(stderr, "legacy_scenario: the host called a field beyond struct_size\n");
  abort();
}

static const clothlab_scenario scenario = {
    CLOTHLAB_SCENARIO_SIZE_1_0,
    0,
    "legacy-pair",
    "Pinned pair from ABI 1.2",
    "1.0.0",
    "two particles, one pinned; a scenario struct of the ABI 1.2 size",
    0,
    0,
    NULL,
    create,
    describe,
    destroy,
    read_past_struct_size};
static const clothlab_scenario* const scenarios[] = {&scenario};

static const clothlab_plugin_descriptor descriptor = {{CLOTHLAB_ABI_VERSION_MAJOR, 2u},
                                                      CLOTHLAB_DESCRIPTOR_SIZE_1_0,
                                                      0,
                                                      1,
                                                      0,
                                                      "clothlab-test-legacy-scenario",
                                                      "1.0.0",
                                                      NULL,
                                                      scenarios};

CLOTHLAB_EXPORT const clothlab_plugin_descriptor* clothlab_plugin_entry(void) {
  return &descriptor;
}
