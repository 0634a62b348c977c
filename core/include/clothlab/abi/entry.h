/*
 * ClothLab plugin ABI: the one symbol a library exports and the descriptor it returns, whose
 * first field is the ABI version the host checks before reading anything else.
 */
#ifndef CLOTHLAB_ABI_ENTRY_H
#define CLOTHLAB_ABI_ENTRY_H

#include <clothlab/abi/integrator.h>
#include <clothlab/abi/scenario.h>
#include <clothlab/abi/version.h>

#ifdef __cplusplus
extern "C" {
#endif

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
  const char* library_name;    /* "clothlab-builtin-rk4" */
  const char* library_version; /* "1.0.0" */
  const clothlab_integrator* const* integrators;
  const clothlab_scenario* const* scenarios;
} clothlab_plugin_descriptor;

#define CLOTHLAB_PLUGIN_ENTRY_SYMBOL "clothlab_plugin_entry"
typedef const clothlab_plugin_descriptor* (*clothlab_plugin_entry_fn)(void);

/* The one symbol a plugin library exports. Returns a pointer to static data. */
CLOTHLAB_EXPORT const clothlab_plugin_descriptor* clothlab_plugin_entry(void);

#define CLOTHLAB_DESCRIPTOR_SIZE_1_0 CLOTHLAB_FIELD_END(clothlab_plugin_descriptor, scenarios)

#ifdef __cplusplus
}
#endif

#endif /* CLOTHLAB_ABI_ENTRY_H */
