#!/usr/bin/env bash
# CPU time to reach a target RMSE, per shading mode: runs `plumage bench` (its
# ladder of sample counts against a high-sample reference of the same mode) and
# interpolates log RMSE against log CPU seconds between the two rungs around the
# target (docs/perf/render.md, "Time to a target error").
#   scripts/speed_at_error.sh TARGET CSV [bench options...]
#   e.g. scripts/speed_at_error.sh 0.01 /tmp/ladder.csv --spp 16,32,64,128 --reference-spp 2048
# Environment: PLUMAGE (the binary, default build/plumage).
set -euo pipefail
cd "$(dirname "$0")/.."
target=${1:?target RMSE}
csv=${2:?CSV output}
shift 2
plumage=${PLUMAGE:-build/plumage}
echo "machine: $(nproc) cores, $(lscpu | sed -n 's/^Model name: *//p'); load: $(cut -d' ' -f1-3 /proc/loadavg)"
"$plumage" -q bench --csv "$csv" --plot "${csv%.csv}.png" --max-slope 100 "$@"
cat "$csv"
awk -F, -v target="$target" -v by=mode -f scripts/time_to_error.awk "$csv"
