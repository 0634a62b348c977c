/*
 * Host extension "clothlab.grid/1": the cloth is a regular grid of rows x cols particles,
 * particle r * cols + c, and the topology's spring colours (clothlab.topology/1) are
 * stencils on it, for methods that work on the grid a row at a time instead of spring by
 * spring (XPBD's row kernels). A host offers it only for a cloth laid out as such a grid;
 * without it a plugin must take the cloth for a general mesh.
 *
 * Lifetime: every array is owned by the host and valid until the system is destroyed;
 * it never changes while the system lives. Thread rule: `get` may be called from any
 * thread; its first call per system may allocate, so call it from `prepare`.
 */
#ifndef CLOTHLAB_EXT_GRID_H
#define CLOTHLAB_EXT_GRID_H

#include <clothlab/plugin.h>

#ifdef __cplusplus
extern "C" {
#endif

#define CLOTHLAB_EXT_GRID "clothlab.grid/1"

/* One spring colour of the topology as a stencil at a parity: its springs join (r, c) to
 * (r + row_step, c + col_step) for every start (r, c) with r in [0, row_end), c in
 * [col_begin, col_end) and (along / step) % 2 == parity, where along and step are c and
 * col_step for a stencil within a row (row_step 0), r and row_step otherwise. Two starts
 * one step apart alternate, so no two springs of the colour share a particle. All springs of
 * a colour have one rest length, ks and kd. A colour whose family has ks = kd = 0 lists no
 * springs in the topology but keeps its stencil here. */
typedef struct clothlab_grid_color {
  uint32_t row_step;
  int32_t col_step;
  uint32_t parity;
  uint32_t row_end;
  uint32_t col_begin;
  uint32_t col_end;
} clothlab_grid_color;

typedef struct clothlab_grid {
  uint32_t struct_size;
  uint32_t rows;
  uint32_t cols;
  uint32_t spring_color_count; /* the topology's spring_color_count */
  /* Rest distances (m) between neighbouring columns and rows of the initial layout,
   * 0 where there is only one. */
  double column_spacing;
  double row_spacing;
  /* spring_color_count entries, colour c of the topology at spring_colors[c]; NULL when the
   * topology's colours are not stencils (e.g. a first-fit colouring). On the Provot grid:
   * 12 colours, the stencils (0, 1), (1, 0), (1, 1), (1, -1), (0, 2), (2, 0) at parity 0
   * then 1. */
  const clothlab_grid_color *spring_colors;
} clothlab_grid;

typedef struct clothlab_grid_extension {
  /* Fills *out (the caller sets out->struct_size). CLOTHLAB_ERROR_OUT_OF_MEMORY when the
   * first call cannot allocate. */
  clothlab_status (*get)(void *context, clothlab_grid *out);
} clothlab_grid_extension;

#ifdef __cplusplus
}
#endif

#endif /* CLOTHLAB_EXT_GRID_H */
