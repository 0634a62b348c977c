/*
 * ClothLab plugin ABI: errors are status codes plus a one-line message written into a
 * caller-owned buffer. No exception, longjmp or C++ type ever crosses the boundary.
 */
#ifndef CLOTHLAB_ABI_STATUS_H
#define CLOTHLAB_ABI_STATUS_H

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef int32_t clothlab_status;
#define CLOTHLAB_OK 0
#define CLOTHLAB_ERROR_INVALID_ARGUMENT 1 /* a parameter or input is out of range */
#define CLOTHLAB_ERROR_UNSUPPORTED 2      /* e.g. a precision the plugin lacks */
#define CLOTHLAB_ERROR_OUT_OF_MEMORY 3
#define CLOTHLAB_ERROR_NUMERICAL 4 /* the step produced or met a non-finite value */
#define CLOTHLAB_ERROR_INTERNAL 5  /* anything else, e.g. a caught exception */

#define CLOTHLAB_MESSAGE_CAPACITY 512
/* Caller-owned buffer; the callee writes a NUL-terminated one-line message when it
 * returns a status other than CLOTHLAB_OK. */
typedef struct clothlab_message {
  char text[CLOTHLAB_MESSAGE_CAPACITY];
} clothlab_message;

#ifdef __cplusplus
}
#endif

#endif /* CLOTHLAB_ABI_STATUS_H */
