#!/usr/bin/env bash
# CPU time to a target RMSE, plumage against pbrt-v3, on the same exported scene
# (docs/perf/render.md, "Against pbrt-v3 at equal error"). Not part of the tests.
# Each renderer's ladder of sample counts is scored against its own high-sample
# reference (pbrt: its "random" sampler, the ladder its "halton"; plumage: another
# seed), RMSE over all pixels and channels (oiiotool --diff), CPU = user + system
# time of the whole process (/usr/bin/time), both with 2 threads.
#   scripts/speed_vs_pbrt.sh [TARGET_RMSE]
# Environment: PBRT (default /work/peers/pbrt-v3/build/pbrt; scripts/check_exports.sh
# builds it), PLUMAGE (build/plumage), OUT (/tmp/plumage_vs_pbrt), RES (48x72),
# SPP (4,8,16,32,64), REF_SPP (2048), WIDTH (empty: the vane's W; "2r": 2 x radius),
# SCENE_ARGS (--lights none --env 1 --backdrop none: the feather alone, white sky).
set -euo pipefail
cd "$(dirname "$0")/.."
root=$PWD
target=${1:-0.01}
PBRT=${PBRT:-/work/peers/pbrt-v3/build/pbrt}
PLUMAGE=$(realpath "${PLUMAGE:-build/plumage}")
OUT=${OUT:-/tmp/plumage_vs_pbrt}
RES=${RES:-48x72}
SPP=${SPP:-4,8,16,32,64}
REF_SPP=${REF_SPP:-2048}
read -r -a scene <<<"${SCENE_ARGS:---lights none --env 1 --backdrop none}"
width=()
[ "${WIDTH:-}" = 2r ] && width=(--ribbon-width 0)
[ -x "$PBRT" ] || { echo "speed_vs_pbrt: error: no pbrt-v3 at $PBRT: run scripts/check_exports.sh first" >&2; exit 1; }
mkdir -p "$OUT"
cd "$OUT"
echo "machine: $(nproc) cores, $(lscpu | sed -n 's/^Model name: *//p'); load: $(cut -d' ' -f1-3 /proc/loadavg)"
"$PLUMAGE" -q generate --preset rock-dove-wing --seed 1 -o dove.fcurves
cpu() { /usr/bin/time -f "%U %S" "$@" 2>&1 >/dev/null | tail -1 | awk '{print $1 + $2}'; }
rms() { oiiotool --diff "$1" "$2" 2>&1 | sed -n 's/.*RMS error = //p'; }
pbrt_scene() {  # SPP SAMPLER NAME
  "$PLUMAGE" -q export dove.fcurves --format pbrt-v3 -o "$3.pbrt" --resolution "$RES" --spp "$1" "${width[@]}" "${scene[@]}"
  sed -i "s/^Sampler \"halton\"/Sampler \"$2\"/; s/\"string filename\" \[ \"[^\"]*\" \]/\"string filename\" [ \"$3.exr\" ]/" "$3.pbrt"
}
pbrt_scene "$REF_SPP" random pbrt_ref
cpu "$PBRT" --nthreads 2 --quiet pbrt_ref.pbrt >/dev/null
cpu "$PLUMAGE" -q render dove.fcurves -o plumage_ref.exr --resolution "$RES" --spp "$REF_SPP" --seed 99 --threads 2 \
  "${width[@]}" "${scene[@]}" >/dev/null
echo "renderer,spp,cpu_seconds,rmse" > ladder.csv
IFS=, read -r -a rungs <<<"$SPP"
for n in "${rungs[@]}"; do
  pbrt_scene "$n" halton "pbrt_$n"
  t=$(cpu "$PBRT" --nthreads 2 --quiet "pbrt_$n.pbrt")
  echo "pbrt-v3,$n,$t,$(rms "pbrt_$n.exr" pbrt_ref.exr)" >> ladder.csv
  t=$(cpu "$PLUMAGE" -q render dove.fcurves -o "plumage_$n.exr" --resolution "$RES" --spp "$n" --seed 1 --threads 2 \
      "${width[@]}" "${scene[@]}")
  echo "plumage,$n,$t,$(rms "plumage_$n.exr" plumage_ref.exr)" >> ladder.csv
done
cat ladder.csv
awk -F, -v target="$target" -v by=renderer -v compare=1 -f "$root/scripts/time_to_error.awk" ladder.csv
