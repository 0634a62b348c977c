/* A scenario extension of the host tests' good plugin, "clothlab.test-point-echo/1": the
 * instance's row count, so a test sees the instance reach the plugin through a table. */
#ifndef CLOTHLAB_TEST_POINT_ECHO_H
#define CLOTHLAB_TEST_POINT_ECHO_H

#include <stdint.h>

#define CLOTHLAB_TEST_POINT_ECHO "clothlab.test-point-echo/1"

typedef struct clothlab_test_point_echo {
  uint32_t (*rows)(void *instance);
} clothlab_test_point_echo;

#endif
