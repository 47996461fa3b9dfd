#!/usr/bin/env bash
# Builds the libFuzzer targets (clang, ASan+UBSan, build-fuzz/) and runs each for a
# fixed number of inputs, starting from its seed corpus in tests/fuzz/corpus/<target>/
# and an empty scratch corpus. The count is SECONDS times the target's measured
# rate on the 2-core VM (table below), and the random seed is fixed
# (PLUMAGE_FUZZ_SEED, default 1), so a CI run executes exactly the inputs that ran
# here, however fast the machine; 4 x SECONDS is a wall-clock cap on top. Set
# another seed, or more seconds, to explore further.
#   scripts/fuzz.sh [SECONDS]        default 60 s' worth of inputs per target
#   BUILD_DIR=... JOBS=N TARGETS="fcurves feather_params" scripts/fuzz.sh 30
# Exits non-zero on the first finding (crash, sanitizer report, hang > 10 s, an
# exception other than plumage::Error, a broken round trip); the input that
# triggered it is saved under $BUILD_DIR/findings/. docs/robustness.md explains.
# Targets: fcurves, feather_params, image, argv, layout (the layout.json reader) and
# fscene (the scene reader).
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-60}
build=${BUILD_DIR:-build-fuzz}
jobs=${JOBS:-$(nproc)}
default_targets="fcurves feather_params image argv layout fscene"
targets=${TARGETS:-$default_targets}

cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_COMPILER=clang++ \
  -DPLUMAGE_FUZZ=ON -DPLUMAGE_BUILD_BENCH=OFF >/dev/null
build_targets=()
for t in $targets; do build_targets+=("fuzz_$t"); done
cmake --build "$build" -j "$jobs" --target "${build_targets[@]}"

# Inputs per second of each target on the 2-core VM (docs/perf/robust.md).
declare -A rate=([fscene]=40000 [fcurves]=40000 [feather_params]=20000 [layout]=15000 [image]=400 [argv]=300)

mkdir -p "$build/findings"
# Decoder messages stay on stderr: read_image captures them into its one-line
# error otherwise, and a sanitizer report written meanwhile would vanish with them.
export PLUMAGE_KEEP_STDERR=1
# Leaks are findings too (the parsers own no global caches); abort on the first UB.
export ASAN_OPTIONS=${ASAN_OPTIONS:-abort_on_error=1:detect_leaks=1:intercept_tls_get_addr=0}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}
# The one third-party leak the image reader meets on broken PNGs (see the file).
export LSAN_OPTIONS=${LSAN_OPTIONS:-suppressions=$PWD/scripts/lsan.supp}
status=0
for t in $targets; do
  # New inputs go to a scratch corpus, emptied first so every run repeats the same
  # sequence; the checked-in seeds stay small and reviewed.
  work="$build/corpus/$t"
  rm -rf "$work" "$build/findings/$t"-*
  mkdir -p "$work"
  runs=$(( ${rate[$t]:-1000} * seconds ))
  echo "== fuzz_$t: $runs inputs (about ${seconds} s)"
  if ! "$build/tests/fuzz/fuzz_$t" "$work" "tests/fuzz/corpus/$t" \
      -seed="${PLUMAGE_FUZZ_SEED:-1}" -runs="$runs" -max_total_time=$(( 4 * seconds )) -timeout=10 \
      -rss_limit_mb=2048 -max_len=65536 -print_final_stats=1 -artifact_prefix="$build/findings/$t-" \
      2>"$build/findings/$t.log"; then
    echo "fuzz_$t: FINDING (log: $build/findings/$t.log)"
    grep -E "FUZZ FINDING|ERROR: |runtime error|SUMMARY|Test unit written" "$build/findings/$t.log" | head -20 || true
    # The input itself, so a CI log alone reproduces the finding (base64 -d > FILE).
    for f in "$build/findings/$t"-*; do
      [[ -f "$f" ]] || continue
      echo "input $f ($(stat -c %s "$f") bytes), base64:"
      head -c 4096 "$f" | base64 -w 0
      echo
    done
    status=1
  else
    grep -E "stat::number_of_executed_units|stat::new_units_added" "$build/findings/$t.log" | tr '\n' ' '
    echo
  fi
done
exit $status
