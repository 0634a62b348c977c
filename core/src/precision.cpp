#include <clothlab/core/cloth.hpp>

namespace clothlab {

const char* to_string(Precision precision) {
  return precision == Precision::Float32 ? "float32" : "float64";
}

}  // namespace clothlab
