/*
 * Plugin extension "clothlab.text-parameters/1" (ABI 1.3): parameters whose value is text, such
 * as the file a scenario reads (`scenario.file=assets/meshes/curtain.obj`), beside the numeric
 * clothlab_param_spec ones. An integrator offers it through its descriptor's get_extension, a
 * scenario through its own.
 *
 * A host that knows the id validates a text value against its spec (any text of at most
 * max_length bytes without a NUL or a line break), resolves a CLOTHLAB_TEXT_PATH value given as
 * a relative path (a host that read the key from a configuration file resolves it against that
 * file's folder, one given on the command line against the working directory) and creates the
 * instance with this table's `create`, which takes the numbers as the descriptor's `create`
 * does plus one text per spec, in spec order. A host that does not know the id never offers the
 * keys and calls the descriptor's `create`: the plugin then takes every text's default.
 *
 * Text names share the namespace of the component's numeric parameter names ([a-z0-9_.]+,
 * unique across both lists). The table and its specs are static.
 */
#ifndef CLOTHLAB_EXT_TEXT_PARAMETERS_H
#define CLOTHLAB_EXT_TEXT_PARAMETERS_H

#include <clothlab/plugin.h>

#ifdef __cplusplus
extern "C" {
#endif

#define CLOTHLAB_EXT_TEXT_PARAMETERS "clothlab.text-parameters/1"

/* The value names a file: the host makes a relative path absolute as described above. */
#define CLOTHLAB_TEXT_PATH (1u << 0)

typedef struct clothlab_text_param_spec {
  uint32_t struct_size;
  uint32_t flags;           /* CLOTHLAB_TEXT_* */
  const char* name;         /* "file" */
  const char* help;         /* one line */
  const char* default_text; /* never NULL; "" allowed */
  uint32_t max_length;      /* bytes, >= 1 */
  uint32_t reserved0;
} clothlab_text_param_spec;

typedef struct clothlab_text_parameters_extension {
  uint32_t struct_size;
  uint32_t count;
  const clothlab_text_param_spec* specs;
  /* As the descriptor's create, plus `texts`: text_count NUL-terminated strings, one per spec,
   * in spec order, valid during the call only. */
  clothlab_status (*create)(const clothlab_param_value* values, uint32_t value_count,
                            const char* const* texts, uint32_t text_count, void** out_instance,
                            clothlab_message* error);
} clothlab_text_parameters_extension;

#define CLOTHLAB_TEXT_PARAM_SPEC_SIZE_1 CLOTHLAB_FIELD_END(clothlab_text_param_spec, reserved0)
#define CLOTHLAB_TEXT_PARAMETERS_SIZE_1 \
  CLOTHLAB_FIELD_END(clothlab_text_parameters_extension, create)

#ifdef __cplusplus
}
#endif

#endif /* CLOTHLAB_EXT_TEXT_PARAMETERS_H */
