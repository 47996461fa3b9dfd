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
awk -F, -v t="$target" '
  NR == 1 { for (i = 1; i <= NF; ++i) col[$i] = i; next }
  { m = $col["mode"]; n[m]++; c[m, n[m]] = $col["cpu_seconds"]; e[m, n[m]] = $col["rmse"]; s[m, n[m]] = $col["spp"] }
  END {
    for (m in n) {
      found = 0
      for (k = 1; k < n[m]; ++k)
        if (e[m, k] >= t && e[m, k + 1] <= t) {
          f = (log(t) - log(e[m, k])) / (log(e[m, k + 1]) - log(e[m, k]))
          cpu = exp(log(c[m, k]) + f * (log(c[m, k + 1]) - log(c[m, k])))
          spp = exp(log(s[m, k]) + f * (log(s[m, k + 1]) - log(s[m, k])))
          printf "%s: RMSE %g at %.3f CPU s (%.0f spp)\n", m, t, cpu, spp
          found = 1
        }
      if (!found) printf "%s: RMSE %g not bracketed by the ladder\n", m, t
    }
  }' "$csv"
