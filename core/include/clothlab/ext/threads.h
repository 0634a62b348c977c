/*
 * Host extension "clothlab.threads/1": how many threads the host lets the work on this system
 * use (the clothlab CLI's --threads / `threads` key, PipelineOptions::threads; 0, "all", is
 * resolved to the hardware's count). A plugin that runs loops of its own in parallel (OpenMP,
 * std::thread) keeps to it, so that a host that runs sweep cases side by side, or a game that
 * gives the cloth one core, is not oversubscribed. The host itself runs clouds below its
 * threading threshold on the calling thread whatever the count.
 *
 * Static table; any thread, any time. Never allocates.
 */
#ifndef CLOTHLAB_EXT_THREADS_H
#define CLOTHLAB_EXT_THREADS_H

#include <clothlab/plugin.h>

#ifdef __cplusplus
extern "C" {
#endif

#define CLOTHLAB_EXT_THREADS "clothlab.threads/1"

typedef struct clothlab_threads_extension {
  /* The thread count, at least 1. */
  uint32_t (*count)(void *context);
} clothlab_threads_extension;

#ifdef __cplusplus
}
#endif

#endif /* CLOTHLAB_EXT_THREADS_H */
