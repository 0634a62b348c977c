#include "clothlab/host/errors.hpp"

namespace clothlab::host {

const char* status_name(clothlab_status status) {
  switch (status) {
    case CLOTHLAB_OK:
      return "ok";
    case CLOTHLAB_ERROR_INVALID_ARGUMENT:
      return "invalid argument";
    case CLOTHLAB_ERROR_UNSUPPORTED:
      return "unsupported";
    case CLOTHLAB_ERROR_OUT_OF_MEMORY:
      return "out of memory";
    case CLOTHLAB_ERROR_NUMERICAL:
      return "numerical failure";
    case CLOTHLAB_ERROR_INTERNAL:
      return "internal error";
    default:
      return "unknown status";
  }
}

}  // namespace clothlab::host
