#!/usr/bin/env bash
# CI's one extra build, ./build-check: portable (no -march=native, what packagers ship) with the
# host and the `boundary` tests instrumented by AddressSanitizer and UndefinedBehaviorSanitizer
# (CLOTHLAB_SANITIZE=host). Builds and runs the tests of one label (tests/CMakeLists.txt):
#   check-build.sh boundary [ctest args]   input, files, child processes, the loader, the plugin
#                                          boundary, under the sanitizers
#   check-build.sh kernels [ctest args]    the core's and the plugins' kernels, portable code
# Only the executables of the label are built; the second label reuses what the first built.
# Prints one summary line (and, on failure, the failed tests with the lines that say why); the
# exit status is ctest's. UBSan halts on its first report (it only logs by default), so
# undefined behaviour fails a test.
set -euo pipefail
cd "$(dirname "$0")/.."
label="${1:?usage: check-build.sh boundary|kernels [ctest args]}"
shift
case "$label" in
  boundary | kernels) ;;
  *)
    echo "check-build.sh: unknown label '$label'; allowed: boundary, kernels" >&2
    exit 2
    ;;
esac
build="build-check"
# Ninja for a new tree, as in tools/build.sh.
if command -v ninja >/dev/null; then export CMAKE_GENERATOR="${CMAKE_GENERATOR:-Ninja}"; fi
cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Release -DCLOTHLAB_NATIVE=OFF -DCLOTHLAB_SANITIZE=host \
  -DCLOTHLAB_BUILD_BENCH=OFF >/dev/null
cmake --build "$build" -j "$(nproc)" --target "tests_$label"
export UBSAN_OPTIONS="${UBSAN_OPTIONS:-halt_on_error=1:print_stacktrace=1}"
log="$build/$label-ctest.log"
status=0
ctest --test-dir "$build" --output-on-failure --timeout 900 -j "$(nproc)" -L "$label" "$@" >"$log" 2>&1 ||
  status=$?
summary=$(grep -E "tests passed|No tests were found" "$log" | tail -n 1 || true)
echo "check-build $label: ${summary:-no ctest summary}; ctest exit status $status; log $log"
if [ "$status" -ne 0 ]; then
  # The log stays in the build tree, which CI throws away: show what failed and why.
  sed -n '/The following tests FAILED/,$p' "$log"
  grep -n -E "^[0-9]+/[0-9]+ Test +#[0-9]+: .*\*\*\*|ERROR: AddressSanitizer|runtime error:|Failure$|\[  FAILED  \]" "$log" |
    head -n 60 || true
fi
exit "$status"
