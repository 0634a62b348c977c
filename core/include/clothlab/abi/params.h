/*
 * ClothLab plugin ABI: the schema of a plugin's parameters and their values. Strings in a
 * spec are static: valid while the library is loaded.
 */
#ifndef CLOTHLAB_ABI_PARAMS_H
#define CLOTHLAB_ABI_PARAMS_H

#include <clothlab/abi/version.h>

#ifdef __cplusplus
extern "C" {
#endif

#define CLOTHLAB_PARAM_REAL 1u /* double in [min, max] */
#define CLOTHLAB_PARAM_INT 2u  /* integer stored in a double, in [min, max] */
#define CLOTHLAB_PARAM_BOOL 3u /* 0 or 1 */
#define CLOTHLAB_PARAM_VEC3 4u /* three doubles, each in [min, max] */

/* Schema of one parameter. The host validates values against it before `create`;
 * plugins validate again and reject bad values with an error. */
typedef struct clothlab_param_spec {
  uint32_t struct_size;
  uint32_t type;           /* CLOTHLAB_PARAM_* */
  const char* name;        /* "structural.ks": [a-z0-9_.]+, unique per component */
  const char* help;        /* one line */
  const char* unit;        /* "N/m", "kg", "" */
  double default_value[3]; /* VEC3 uses all three; other types use [0] */
  double min_value;        /* inclusive; per component for VEC3 */
  double max_value;        /* inclusive */
} clothlab_param_spec;

#define CLOTHLAB_PARAM_SPEC_SIZE_1_0 CLOTHLAB_FIELD_END(clothlab_param_spec, max_value)

/* One value per spec, in spec order. Scalars use v[0]. */
typedef struct clothlab_param_value {
  double v[3];
} clothlab_param_value;

#ifdef __cplusplus
}
#endif

#endif /* CLOTHLAB_ABI_PARAMS_H */
