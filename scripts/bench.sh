#!/usr/bin/env bash
# Builds and runs the micro-benchmarks (Google Benchmark), or the error ladder.
#   scripts/bench.sh                     every benchmark
#   scripts/bench.sh --benchmark_filter=Hair   any Google Benchmark flag
#   scripts/bench.sh --ladder [ARGS]     `plumage bench` (run time against error,
#                                        docs/benchladder.md); ARGS go to it, e.g.
#                                        --preset osprey-wing-covert --spp 1,4,16,64
#                                        Writes build/benchladder.csv and .png unless
#                                        --csv/--plot say otherwise; exits non-zero
#                                        when a mode's error stops falling.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
build=${BUILD_DIR:-build}
cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Release >/dev/null
echo "machine: $(nproc) cores, $(lscpu | sed -n 's/^Model name: *//p'), $(free -g | awk '/Mem:/{print $2}') GiB"
if [[ "${1:-}" == "--ladder" ]]; then
  shift
  cmake --build "$build" -j "$(nproc)" --target plumage
  "$build/plumage" bench --csv "$build/benchladder.csv" --plot "$build/benchladder.png" "$@"
  exit
fi
cmake --build "$build" -j "$(nproc)" --target plumage_bench
"$build/plumage_bench" "$@"
