/* A plugin from a later minor version of ABI 1: its descriptor has fields appended after
 * the ones this host knows. The host must accept it and ignore the extra fields. */
#include <clothlab/plugin.h>

typedef struct later_minor_descriptor {
  clothlab_plugin_descriptor known;
  uint64_t appended_field;
} later_minor_descriptor;

static const later_minor_descriptor descriptor = {{{CLOTHLAB_ABI_VERSION_MAJOR, 99u},
                                                   sizeof(later_minor_descriptor),
                                                   0,
                                                   0,
                                                   0,
                                                   "clothlab-test-future-minor",
                                                   "0.1.0",
                                                   NULL,
                                                   NULL},
                                                  42u};

const clothlab_plugin_descriptor* clothlab_plugin_entry(void) { return &descriptor.known; }
