/* A plugin built against an ABI major this host cannot read. */
#include <clothlab/plugin.h>

static const clothlab_plugin_descriptor descriptor = {
    {999u, 0u}, sizeof(clothlab_plugin_descriptor), 0, 0, 0, "clothlab-test-abi999", "0.1.0", NULL,
    NULL};

const clothlab_plugin_descriptor* clothlab_plugin_entry(void) { return &descriptor; }
