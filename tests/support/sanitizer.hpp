// Whether this test binary is built with AddressSanitizer (CLOTHLAB_SANITIZE): a crash in a
// child process then shows as ASan's report and a non-zero exit instead of a signal.
#pragma once

namespace clothlab::testing {

// GCC marks an AddressSanitizer build with a macro, Clang with a feature test.
#if defined(__SANITIZE_ADDRESS__)
inline constexpr bool address_sanitizer = true;
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
inline constexpr bool address_sanitizer = true;
#else
inline constexpr bool address_sanitizer = false;
#endif
#else
inline constexpr bool address_sanitizer = false;
#endif

}  // namespace clothlab::testing
