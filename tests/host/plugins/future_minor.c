/* A plugin from a later minor version of ABI 1: its descriptor has fields appended after
 * the ones this host knows. The host must accept it and ignore the extra fields. Its one
 * scenario is there because a library must provide a component; the tests never create it. */
#include <clothlab/plugin.h>

static clothlab_status create(const clothlab_param_value* values, uint32_t value_count,
                              void** out_instance, clothlab_message* error) {
  (void)values;
  (void)value_count;
  (void)error;
  *out_instance = NULL;
  return CLOTHLAB_ERROR_UNSUPPORTED;
}

static clothlab_status describe(void* instance, clothlab_scene* scene, clothlab_message* error) {
  (void)instance;
  (void)scene;
  (void)error;
  return CLOTHLAB_ERROR_UNSUPPORTED;
}

static void destroy(void* instance) { (void)instance; }

static const clothlab_scenario scenario = {sizeof(clothlab_scenario),
                                           0,
                                           "future-point",
                                           "Future point",
                                           "0.1.0",
                                           "a scenario of a later minor version; for host tests",
                                           0,
                                           0,
                                           NULL,
                                           create,
                                           describe,
                                           destroy,
                                           NULL};
static const clothlab_scenario* const scenarios[] = {&scenario};

typedef struct later_minor_descriptor {
  clothlab_plugin_descriptor known;
  uint64_t appended_field;
} later_minor_descriptor;

static const later_minor_descriptor descriptor = {{{CLOTHLAB_ABI_VERSION_MAJOR, 99u},
                                                   sizeof(later_minor_descriptor),
                                                   0,
                                                   1,
                                                   0,
                                                   "clothlab-test-future-minor",
                                                   "0.1.0",
                                                   NULL,
                                                   scenarios},
                                                  42u};

const clothlab_plugin_descriptor* clothlab_plugin_entry(void) { return &descriptor.known; }
