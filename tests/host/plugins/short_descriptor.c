/* A plugin whose descriptor claims fewer bytes than ABI 1.0 defines. */
#include <clothlab/plugin.h>

static const clothlab_plugin_descriptor descriptor = {
    {CLOTHLAB_ABI_VERSION_MAJOR, 0u}, 16u, 0, 0, 0, "clothlab-test-short", "0.1.0", NULL, NULL};

const clothlab_plugin_descriptor* clothlab_plugin_entry(void) { return &descriptor; }
