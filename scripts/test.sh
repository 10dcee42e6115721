#!/usr/bin/env bash
# The README's test command: installs what is missing, builds, and runs every test
#   0. the source checks: no product function over 80 lines, docs short and their links whole
#   1. AddressSanitizer + UBSan build (-O1 -g1, warnings as errors) -> the whole ctest suite
#   2. ThreadSanitizer build of the threaded suites (label "threaded") -> ctest
# Usage: scripts/test.sh [--plain | --quick]
#   --plain  also run the whole suite on a plain build first (build/, as scripts/run.sh)
#   --quick  only the plain build's suite, for local iteration
set -euo pipefail
cd "$(dirname "$0")/.."
root=$PWD
jobs=$(nproc)
mode=${1:-}
case "$mode" in ""|--plain|--quick) ;; *) echo "usage: scripts/test.sh [--plain | --quick]" >&2; exit 2;; esac

bash scripts/setup.sh

echo "=== source checks"
bash scripts/check_function_length.sh
bash scripts/check_docs.sh

# Isolate tests from the developer's OpenXR/Vulkan configuration.
export LSAN_OPTIONS="suppressions=$root/tests/sanitizers/lsan.supp:print_suppressions=0"
# intercept_tls_get_addr=0: GCC 12's (and LLVM <= 16's) __tls_get_addr interceptor takes a dynamic
# TLS block that malloc happens to place 16 bytes past a page boundary for a pre-2.25 glibc
# header and reads two garbage words as its bounds; LeakSanitizer's tracer then dies at exit
# ("Tracer caught signal 11"), now and then, in the apps that load lavapipe. Static TLS and
# every thread's stack are still scanned.
export ASAN_OPTIONS="detect_leaks=1:verify_asan_link_order=0:intercept_tls_get_addr=0"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
export TSAN_OPTIONS="suppressions=$root/tests/sanitizers/tsan.supp:halt_on_error=1:second_deadlock_stack=1"

run_suite() {  # dir, cmake args..., then ctest label filter in CTEST_ARGS
  local dir=$1; shift
  echo "=== configure $dir ($*)"
  cmake -S . -B "$dir" -G Ninja "$@" >/dev/null
  echo "=== build $dir"
  cmake --build "$dir" -j "$jobs" ${BUILD_TARGET:+--target $BUILD_TARGET}
  echo "=== test $dir"
  ctest --test-dir "$dir" --output-on-failure -j "$jobs" --timeout 600 ${CTEST_ARGS:-}
}

SECONDS=0
if [ -n "$mode" ]; then
  CTEST_ARGS="" run_suite build -DCMAKE_BUILD_TYPE=RelWithDebInfo -DFOVEART_WERROR=ON
  echo "=== plain suite done in ${SECONDS}s"
  [ "$mode" = "--quick" ] && exit 0
fi

CTEST_ARGS="" run_suite build-asan -DCMAKE_BUILD_TYPE=RelWithDebInfo -DFOVEART_BUILD_BENCH=OFF -DFOVEART_WERROR=ON \
  "-DFOVEART_SANITIZE=address;undefined"
echo "=== asan/ubsan suite done in ${SECONDS}s"

BUILD_TARGET=threaded_tests CTEST_ARGS="-L threaded" run_suite build-tsan -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DFOVEART_BUILD_BENCH=OFF -DFOVEART_SANITIZE=thread
echo "=== tsan suite done in ${SECONDS}s"
