// The SDK's error type and the guard that turns exceptions into ABI status codes.
#pragma once

#include <clothlab/plugin.h>

#include <cstring>
#include <exception>
#include <new>
#include <stdexcept>
#include <string>
#include <string_view>

namespace clothlab::sdk {

// An error with a status code; thrown inside a plugin, returned across the ABI.
class Error : public std::runtime_error {
 public:
  Error(clothlab_status status, const std::string& message)
      : std::runtime_error(message), status_(status) {}
  clothlab_status status() const noexcept { return status_; }

 private:
  clothlab_status status_;
};

inline void write_message(clothlab_message* out, std::string_view text) noexcept {
  if (out == nullptr) return;
  const size_t n =
      text.size() < CLOTHLAB_MESSAGE_CAPACITY - 1 ? text.size() : CLOTHLAB_MESSAGE_CAPACITY - 1;
  std::memcpy(out->text, text.data(), n);
  out->text[n] = '\0';
}

// Throws Error(status, what) unless status is CLOTHLAB_OK; NUMERICAL says so.
inline void check(clothlab_status status, const char* what) {
  if (status == CLOTHLAB_OK) return;
  throw Error(status, status == CLOTHLAB_ERROR_NUMERICAL ? std::string(what) + ": non-finite value"
                                                         : std::string(what));
}

// Runs `body`, converting any exception into a status and message.
template <class Body>
clothlab_status guarded(clothlab_message* error, Body&& body) noexcept {
  try {
    body();
    return CLOTHLAB_OK;
  } catch (const Error& e) {
    write_message(error, e.what());
    return e.status();
  } catch (const std::bad_alloc&) {
    write_message(error, "out of memory");
    return CLOTHLAB_ERROR_OUT_OF_MEMORY;
  } catch (const std::exception& e) {
    write_message(error, e.what());
    return CLOTHLAB_ERROR_INTERNAL;
  } catch (...) {
    write_message(error, "unknown exception");
    return CLOTHLAB_ERROR_INTERNAL;
  }
}

}  // namespace clothlab::sdk
