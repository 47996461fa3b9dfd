#!/usr/bin/env bash
# Builds the libFuzzer targets (clang, ASan+UBSan, build-fuzz/) and runs each for a
# bounded time, starting from its seed corpus in tests/fuzz/corpus/<target>/.
# The random seed is fixed (PLUMAGE_FUZZ_SEED, default 1) so a CI run repeats what
# ran here; set another seed, or a longer time, to explore further.
#   scripts/fuzz.sh [SECONDS]        default 60 s per target
#   BUILD_DIR=... JOBS=N TARGETS="fcurves feather_params" scripts/fuzz.sh 30
# Exits non-zero on the first finding (crash, sanitizer report, hang > 10 s, an
# exception other than plumage::Error, a broken round trip); the input that
# triggered it is saved under $BUILD_DIR/findings/. docs/robustness.md explains.
# Targets: fcurves, feather_params, and layout (the analysis layout reader) when
# generator/include/plumage/generator/analysis/layout.h exists.
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-60}
build=${BUILD_DIR:-build-fuzz}
jobs=${JOBS:-$(nproc)}
default_targets="fcurves feather_params image argv"
if [[ -f generator/include/plumage/generator/analysis/layout.h ]]; then
  default_targets+=" layout"
else
  # A checkout without photo analysis (tests/fuzz/CMakeLists.txt skips it too).
  echo "fuzz.sh: analysis/layout.h not present yet: fuzz_layout skipped" >&2
fi
targets=${TARGETS:-$default_targets}

cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_COMPILER=clang++ \
  -DPLUMAGE_FUZZ=ON -DPLUMAGE_BUILD_BENCH=OFF >/dev/null
build_targets=()
for t in $targets; do build_targets+=("fuzz_$t"); done
cmake --build "$build" -j "$jobs" --target "${build_targets[@]}"

mkdir -p "$build/findings"
# Leaks are findings too (the parsers own no global caches); abort on the first UB.
export ASAN_OPTIONS=${ASAN_OPTIONS:-abort_on_error=1:detect_leaks=1}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}
# The one third-party leak the image reader meets on broken PNGs (see the file).
export LSAN_OPTIONS=${LSAN_OPTIONS:-suppressions=$PWD/scripts/lsan.supp}
status=0
for t in $targets; do
  # New inputs go to a scratch corpus so the checked-in seeds stay small and reviewed.
  work="$build/corpus/$t"
  mkdir -p "$work"
  echo "== fuzz_$t for ${seconds} s"
  if ! "$build/tests/fuzz/fuzz_$t" "$work" "tests/fuzz/corpus/$t" \
      -seed="${PLUMAGE_FUZZ_SEED:-1}" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 -max_len=65536 \
      -print_final_stats=1 -artifact_prefix="$build/findings/$t-" 2>"$build/findings/$t.log"; then
    echo "fuzz_$t: FINDING (log: $build/findings/$t.log)"
    grep -E "FUZZ FINDING|ERROR: |runtime error|SUMMARY" "$build/findings/$t.log" | head -20 || true
    status=1
  else
    grep -E "stat::number_of_executed_units|stat::new_units_added" "$build/findings/$t.log" | tr '\n' ' '
    echo
  fi
done
exit $status
