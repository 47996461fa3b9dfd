#!/usr/bin/env bash
# Builds and runs the micro-benchmarks (Google Benchmark).
#   scripts/bench.sh                     every benchmark
#   scripts/bench.sh --benchmark_filter=Hair   any Google Benchmark flag
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
build=${BUILD_DIR:-build}
cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$build" -j "$(nproc)" --target plumage_bench
echo "machine: $(nproc) cores, $(lscpu | sed -n 's/^Model name: *//p'), $(free -g | awk '/Mem:/{print $2}') GiB"
"$build/plumage_bench" "$@"
