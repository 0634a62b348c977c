/*
 * ClothLab plugin ABI: the version a library was built against, the one compatibility rule
 * and the struct-size rule every reader follows (see clothlab/plugin.h for the whole ABI).
 */
#ifndef CLOTHLAB_ABI_VERSION_H
#define CLOTHLAB_ABI_VERSION_H

#include <stddef.h>
#include <stdint.h>

#define CLOTHLAB_ABI_VERSION_MAJOR 1u
#define CLOTHLAB_ABI_VERSION_MINOR 3u

#if defined(__GNUC__) || defined(__clang__)
#define CLOTHLAB_EXPORT __attribute__((visibility("default")))
#else
#define CLOTHLAB_EXPORT
#endif

#ifdef __cplusplus
extern "C" {
#endif

typedef struct clothlab_abi_version {
  uint32_t major;
  uint32_t minor;
} clothlab_abi_version;

/* The one compatibility rule, used by the host's loader, the SDK and the conformance
 * runner: same major, any minor. */
static inline int clothlab_abi_is_compatible(clothlab_abi_version plugin_version) {
  return plugin_version.major == CLOTHLAB_ABI_VERSION_MAJOR;
}

/* A reader accepts any struct_size >= the struct's 1.0 size (CLOTHLAB_*_SIZE_1_0, beside each
 * struct) and reads a field only when CLOTHLAB_HAS_FIELD says the struct covers it. */
#define CLOTHLAB_FIELD_END(type, field) (offsetof(type, field) + sizeof(((type*)0)->field))
#define CLOTHLAB_HAS_FIELD(pointer, type, field) \
  ((size_t)(pointer)->struct_size >= CLOTHLAB_FIELD_END(type, field))

#ifdef __cplusplus
}
#endif

#endif /* CLOTHLAB_ABI_VERSION_H */
