/*
 * ClothLab plugin ABI: a scenario's descriptor, the grid scene it describes and its
 * extensions (colliders, air, attachments, a mesh: clothlab/ext/).
 */
#ifndef CLOTHLAB_ABI_SCENARIO_H
#define CLOTHLAB_ABI_SCENARIO_H

#include <clothlab/abi/params.h>
#include <clothlab/abi/status.h>
#include <clothlab/abi/version.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef struct clothlab_spring_family {
  double ks; /* Hooke stiffness, N/m */
  double kd; /* linear damping along the spring, N s/m */
} clothlab_spring_family;

/*
 * A regular grid cloth: particle (r, c), index r * cols + c, starts at
 *   origin + c * (width / (cols - 1)) * col_axis + r * (height / (rows - 1)) * row_axis
 * (a 1-wide dimension puts every particle at offset 0 along it). Springs are the Provot
 * stencils, rest lengths taken from this initial layout: structural (0,1),(1,0);
 * shear (1,1),(1,-1); flexion (0,2),(2,0). Mass is spread evenly; pinned particles get
 * inverse mass 0. Wind acts on each grid triangle as a pressure along its normal:
 * F = wind_strength * area * (n . wind_direction) n, shared equally by its 3 corners.
 */
typedef struct clothlab_scene {
  uint32_t struct_size;
  uint32_t rows;
  uint32_t cols;
  uint32_t pinned_count;
  const uint32_t* pinned; /* particle indices; valid until the instance is destroyed */
  double width;           /* metres along col_axis */
  double height;          /* metres along row_axis */
  double origin[3];
  double col_axis[3]; /* unit */
  double row_axis[3]; /* unit */
  double total_mass;  /* kg */
  clothlab_spring_family structural;
  clothlab_spring_family shear;
  clothlab_spring_family flexion;
  double gravity[3];        /* m/s^2 */
  double wind_direction[3]; /* unit; ignored when wind_strength is 0 */
  double wind_strength;     /* N/m^2; 0 = no wind stage at all */
} clothlab_scene;

typedef struct clothlab_scenario {
  uint32_t struct_size;
  uint32_t reserved0;
  const char* id;          /* "flag" */
  const char* name;        /* "Flag in wind" */
  const char* version;     /* "1.0.0" */
  const char* description; /* one line */
  uint32_t param_count;
  uint32_t reserved1;
  const clothlab_param_spec* params;

  clothlab_status (*create)(const clothlab_param_value* values, uint32_t value_count,
                            void** out_instance, clothlab_message* error);
  /* Fills *scene. The host sets scene->struct_size before the call. */
  clothlab_status (*describe)(void* instance, clothlab_scene* scene, clothlab_message* error);
  void (*destroy)(void* instance);

  /* ---- since 1.3: present when struct_size covers it; the last field ever added ---- */

  /* The scenario extension with this id, or NULL. May be NULL itself (no extensions).
   * Returns static data; any thread, any time, without an instance. Tables whose
   * functions concern one scene take the instance `create` made as their first argument. */
  const void* (*get_extension)(const char* id);
} clothlab_scenario;

#define CLOTHLAB_SCENARIO_SIZE_1_0 CLOTHLAB_FIELD_END(clothlab_scenario, destroy)
#define CLOTHLAB_SCENARIO_SIZE_1_3 CLOTHLAB_FIELD_END(clothlab_scenario, get_extension)
#define CLOTHLAB_SCENE_SIZE_1_0 CLOTHLAB_FIELD_END(clothlab_scene, wind_strength)

/* The one safe way to look an extension up: NULL when the struct predates the field (1.2 for a
 * system or an integrator, 1.3 for a scenario), when the field is NULL, or when the other side
 * does not offer `id`. */
static inline const void* clothlab_scenario_extension(const clothlab_scenario* scenario,
                                                      const char* id) {
  if (!CLOTHLAB_HAS_FIELD(scenario, clothlab_scenario, get_extension) || !scenario->get_extension)
    return NULL;
  return scenario->get_extension(id);
}

#ifdef __cplusplus
}
#endif

#endif /* CLOTHLAB_ABI_SCENARIO_H */
