#!/usr/bin/env bash
# Builds the unit tests with AddressSanitizer + UndefinedBehaviorSanitizer
# (PLUMAGE_SANITIZE=ON, -O1, build-asan/) and runs them as ONE process (a process
# per test would cost ~0.4 s each under ASan). Halts on the first report.
#   scripts/sanitize.sh [gtest filter]      default: every test
#   BUILD_DIR=... JOBS=N scripts/sanitize.sh
# The stress tests run their default 10^6 BCSDF inputs here; CI runs the full 10^7
# (PLUMAGE_STRESS=1) once, in the faster Release run (docs/robustness.md).
set -euo pipefail
cd "$(dirname "$0")/.."
build=${BUILD_DIR:-build-asan}
jobs=${JOBS:-$(nproc)}
filter=${1:-*}

# -O1: ASan's own advice for usable speed with exact reports; no benchmarks.
cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g" \
  -DPLUMAGE_SANITIZE=ON -DPLUMAGE_BUILD_BENCH=OFF >/dev/null
cmake --build "$build" -j "$jobs" --target plumage_tests

# Leak reports are on; scripts/lsan.supp lists the only third-party allocations
# that are deliberately never freed (docs/robustness.md says which and why).
# intercept_tls_get_addr=0: GCC 12's runtime guesses a dynamic-TLS block's range from
# its address (a pre-2.25 glibc header when the address is 16 mod 4096), so a block
# that lands there by chance hands LeakSanitizer a bogus range and its tracer dies
# at exit ("Tracer caught signal 11") after every test passed (docs/robustness.md).
export ASAN_OPTIONS=${ASAN_OPTIONS:-halt_on_error=1:abort_on_error=1:detect_leaks=1:strict_string_checks=1:detect_stack_use_after_return=1:intercept_tls_get_addr=0}
export LSAN_OPTIONS=${LSAN_OPTIONS:-suppressions=$PWD/scripts/lsan.supp:print_suppressions=0}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}
"$build/plumage_tests" --gtest_filter="$filter" --gtest_brief=1
