#!/usr/bin/env bash
# Builds ClothLab with AddressSanitizer and UndefinedBehaviorSanitizer (CLOTHLAB_SANITIZE) into
# ./build-asan and runs the tests labelled `boundary` there (input parsing, files, child
# processes, the loader and the plugin boundary; tests/CMakeLists.txt): only their executables
# are built. Prints one summary line at the end (and, on failure, the failed tests with the
# lines that say why); the exit status is ctest's. Extra arguments go to ctest (e.g. -R
# conformance).
# UBSan halts on its first report (it only logs by default), so undefined behaviour fails a test.
set -euo pipefail
cd "$(dirname "$0")/.."
build="build-asan"
cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Release -DCLOTHLAB_SANITIZE=ON \
  -DCLOTHLAB_BUILD_BENCH=OFF >/dev/null
cmake --build "$build" -j2 --target tests_boundary
export UBSAN_OPTIONS="${UBSAN_OPTIONS:-halt_on_error=1:print_stacktrace=1}"
log="$build/sanitize-ctest.log"
status=0
ctest --test-dir "$build" --output-on-failure --timeout 900 -j2 -L boundary "$@" >"$log" 2>&1 ||
  status=$?
summary=$(grep -E "tests passed|No tests were found" "$log" | tail -n 1 || true)
echo "sanitize: ${summary:-no ctest summary}; ctest exit status $status; log $log"
if [ "$status" -ne 0 ]; then
  # The log stays in the build tree, which CI throws away: show what failed and why.
  sed -n '/The following tests FAILED/,$p' "$log"
  grep -n -E "^[0-9]+/[0-9]+ Test +#[0-9]+: .*\*\*\*|ERROR: AddressSanitizer|runtime error:|Failure$|\[  FAILED  \]" "$log" |
    head -n 60 || true
fi
exit "$status"
