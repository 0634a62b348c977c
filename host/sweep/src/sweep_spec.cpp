#include "clothlab/sweep/sweep_spec.hpp"

namespace clothlab::sweep {

const char* to_string(SweepMode mode) {
  switch (mode) {
    case SweepMode::Run:
      return "run";
    case SweepMode::WorkPrecision:
      return "work-precision";
    case SweepMode::Stability:
      return "stability";
  }
  return "unknown";
}

}  // namespace clothlab::sweep
