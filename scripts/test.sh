#!/usr/bin/env bash
# Installs what is missing, configures, builds, runs every test (ctest) and prints the summary.
#   scripts/test.sh            Release build in build/
#   BUILD_DIR=... JOBS=N scripts/test.sh
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
build=${BUILD_DIR:-build}
jobs=${JOBS:-$(nproc)}
cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Release ${CMAKE_ARGS:-} >/dev/null
cmake --build "$build" -j "$jobs"
cd "$build"
ctest --output-on-failure -j "$jobs" --timeout 600
