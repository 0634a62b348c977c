/*
 * Integrator extension "clothlab.explicit-scheme/1": an explicit Runge-Kutta-Nystrom
 * integrator declares its table, so the host derives its evaluations per step and
 * predicts its stability limit from the table (the amplification matrix of
 * x'' = -w^2 x - g x') for any plugin, not only built-in ids. Static data.
 */
#ifndef CLOTHLAB_EXT_EXPLICIT_SCHEME_H
#define CLOTHLAB_EXT_EXPLICIT_SCHEME_H

#include <clothlab/plugin.h>

#ifdef __cplusplus
extern "C" {
#endif

#define CLOTHLAB_EXT_EXPLICIT_SCHEME "clothlab.explicit-scheme/1"

typedef struct clothlab_explicit_scheme {
  uint32_t struct_size;
  /* 1 when the last stage's acceleration is the next step's first (first same as last):
   * evaluations per step are then stages - 1. */
  uint32_t first_same_as_last;
  const clothlab_rkn_scheme *scheme; /* the step the integrator takes */
} clothlab_explicit_scheme;

#ifdef __cplusplus
}
#endif

#endif /* CLOTHLAB_EXT_EXPLICIT_SCHEME_H */
