#!/usr/bin/env bash
# Builds the unit tests with AddressSanitizer + UndefinedBehaviorSanitizer
# (PLUMAGE_SANITIZE=ON, -O1, build-asan/) and runs them as SHARDS processes side by
# side (default: one per core), each holding every SHARDS-th test (GoogleTest's
# sharding), instead of a process per test (~0.4 s each under ASan). A shard halts
# on its first report; the script fails when any shard does and prints its log.
#   scripts/sanitize.sh [gtest filter]      default: every test
#   BUILD_DIR=... JOBS=N SHARDS=N scripts/sanitize.sh
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
shards=${SHARDS:-$(nproc)}
logs=$(mktemp -d)
pids=()
for ((i = 0; i < shards; ++i)); do
  GTEST_TOTAL_SHARDS=$shards GTEST_SHARD_INDEX=$i \
    "$build/plumage_tests" --gtest_filter="$filter" --gtest_brief=1 >"$logs/$i.log" 2>&1 &
  pids+=($!)
done
status=0
for ((i = 0; i < shards; ++i)); do
  if wait "${pids[$i]}"; then
    echo "shard $((i + 1))/$shards: $(grep -E '^\[  PASSED  \]|tests from .* ran' "$logs/$i.log" | tr '\n' ' ')"
  else
    status=1
    echo "shard $((i + 1))/$shards FAILED; its output:"
    cat "$logs/$i.log"
  fi
done
rm -rf "$logs"
exit $status
