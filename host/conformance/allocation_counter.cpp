// Counts allocator calls process-wide. Normally it replaces the allocator entry points with
// counting forwarders to glibc's implementation (__libc_*). In a runner built with
// AddressSanitizer, which owns the allocator, it registers ASan's allocation hooks instead.
// A runner built without it but run with the sanitizer runtime preloaded (LD_PRELOAD=libasan.so,
// to test an ASan-built plugin) forwards to the runtime's allocator: the runtime's own
// interceptors (strdup, ...) allocate there, so a block must be freed there too.
#include "allocation_counter.hpp"

#include <atomic>
#include <cerrno>
#include <cstddef>
#include <new>

#if defined(__SANITIZE_ADDRESS__)
// From the sanitizer runtime (GCC ships the library, not <sanitizer/allocator_interface.h>).
extern "C" int __sanitizer_install_malloc_and_free_hooks(void (*on_allocate)(const volatile void*,
                                                                             size_t),
                                                         void (*on_free)(const volatile void*));
#else
extern "C" {
void* __libc_malloc(size_t size);
void* __libc_calloc(size_t count, size_t size);
void* __libc_realloc(void* pointer, size_t size);
void* __libc_memalign(size_t alignment, size_t size);
void __libc_free(void* pointer);

// Defined only when a sanitizer runtime is loaded (GCC's libasan): its
// allocator, under the names its interceptors keep beside the malloc they export.
__attribute__((weak)) void* __interceptor_malloc(size_t size);
__attribute__((weak)) void* __interceptor_calloc(size_t count, size_t size);
__attribute__((weak)) void* __interceptor_realloc(void* pointer, size_t size);
__attribute__((weak)) void* __interceptor_memalign(size_t alignment, size_t size);
__attribute__((weak)) void __interceptor_free(void* pointer);
}
#endif

namespace {

// Armed and counted process-wide: a plugin's own worker threads allocate outside the thread
// that called step. Paused per thread: the host's code runs on the thread that called it.
std::atomic<bool> armed{false};
std::atomic<uint64_t> calls{0};
// initial-exec: reading the flag must never allocate, even from inside malloc.
__attribute__((tls_model("initial-exec"))) thread_local bool paused = false;

inline void note() {
  if (armed.load(std::memory_order_relaxed) && !paused)
    calls.fetch_add(1, std::memory_order_relaxed);
}

}  // namespace

namespace clothlab::conformance::allocations {

void arm() {
  calls.store(0);
  armed.store(true);
}

uint64_t disarm() {
  armed.store(false);
  return calls.load();
}

Pause::Pause() : was_paused_(paused) { paused = true; }

Pause::~Pause() { paused = was_paused_; }

}  // namespace clothlab::conformance::allocations

#if defined(__SANITIZE_ADDRESS__)

namespace {
void on_allocate(const volatile void*, size_t) { note(); }
void on_free(const volatile void*) { note(); }
const int hooks_installed = __sanitizer_install_malloc_and_free_hooks(on_allocate, on_free);
}  // namespace

#else

namespace {
bool valid_alignment(size_t alignment) {
  return alignment >= sizeof(void*) && (alignment & (alignment - 1)) == 0;
}

// The sanitizer runtime's allocator when one is preloaded, else glibc's. Tested on every call
// (a load from the GOT), not once at start-up: allocations come before any initialiser runs.
void* allocate(size_t size) {
  return __interceptor_malloc ? __interceptor_malloc(size) : __libc_malloc(size);
}

void* allocate_aligned(size_t alignment, size_t size) {
  return __interceptor_memalign ? __interceptor_memalign(alignment, size)
                                : __libc_memalign(alignment, size);
}
}  // namespace

extern "C" {

void* malloc(size_t size) {
  note();
  return allocate(size);
}

void* calloc(size_t count, size_t size) {
  note();
  return __interceptor_calloc ? __interceptor_calloc(count, size) : __libc_calloc(count, size);
}

void* realloc(void* pointer, size_t size) {
  note();
  return __interceptor_realloc ? __interceptor_realloc(pointer, size)
                               : __libc_realloc(pointer, size);
}

void free(void* pointer) {
  if (pointer != nullptr) note();
  if (__interceptor_free)
    __interceptor_free(pointer);
  else
    __libc_free(pointer);
}

void* memalign(size_t alignment, size_t size) {
  note();
  return allocate_aligned(alignment, size);
}

void* aligned_alloc(size_t alignment, size_t size) {
  note();
  return allocate_aligned(alignment, size);
}

int posix_memalign(void** out, size_t alignment, size_t size) {
  note();
  if (!valid_alignment(alignment)) return EINVAL;
  void* pointer = allocate_aligned(alignment, size);
  if (pointer == nullptr) return ENOMEM;
  *out = pointer;
  return 0;
}

}  // extern "C"

void* operator new(size_t size) {
  void* pointer = malloc(size == 0 ? 1 : size);
  if (pointer == nullptr) throw std::bad_alloc();
  return pointer;
}

void* operator new[](size_t size) { return operator new(size); }

void* operator new(size_t size, const std::nothrow_t&) noexcept {
  return malloc(size == 0 ? 1 : size);
}

void* operator new[](size_t size, const std::nothrow_t&) noexcept {
  return malloc(size == 0 ? 1 : size);
}

void operator delete(void* pointer) noexcept { free(pointer); }
void operator delete[](void* pointer) noexcept { free(pointer); }
void operator delete(void* pointer, size_t) noexcept { free(pointer); }
void operator delete[](void* pointer, size_t) noexcept { free(pointer); }
void operator delete(void* pointer, const std::nothrow_t&) noexcept { free(pointer); }
void operator delete[](void* pointer, const std::nothrow_t&) noexcept { free(pointer); }

#endif  // __SANITIZE_ADDRESS__
