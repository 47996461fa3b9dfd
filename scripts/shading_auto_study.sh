#!/usr/bin/env bash
# --shading auto against all-substructure on the rock-dove wing of `plumage wing`
# (docs/substructure.md, "Shading level by footprint"; figures in docs/perf/scene.md).
# Each mode renders the wing twice, seeds 1 and 2, under /usr/bin/time. Reported:
#   CPU s     user + system seconds of one render (the mean of the two seeds)
#   noise     the per-pixel standard deviation of one render: RMS(seed 1 - seed 2) / sqrt 2
#   to noise  CPU seconds to reach noise $TARGET: CPU s x (noise / TARGET)^2
#             (Monte Carlo noise falls as 1/sqrt(spp))
# and, between the modes, the RMS of the difference of their two-seed means and that
# difference with both means' noise taken out (sqrt(D^2 - (noise_a^2 + noise_s^2) / 2)).
# RMS is idiff's (OpenImageIO): over every pixel and channel of the linear EXR.
# Far-field tables are fitted first (a 1x1 render in farfield mode, not timed) into
# $PLUMAGE_FARFIELD_CACHE (default: OUT/farfield-cache).
# Then, against the truth: an explicit render (rami and barbules as real curves,
# docs/substructure.md "Explicit reference") at $ERES and $ESPP spp is the reference,
# and each mode's ladder (4, 16, 64 spp, seed 1) is compared with it: RMSE per rung,
# CPU seconds, and the model error (what the RMSE converges to: RMSE^2(n) = M^2 + s/n
# + the reference's noise^2, s and M from the 16 and 64 spp rungs; the reference's
# noise from an explicit 64 spp render of another seed). ESPP=0 skips this part.
# Usage: scripts/shading_auto_study.sh [OUT] [extra render flags, e.g. a camera...]
# Environment: PLUMAGE (build/plumage), RES (1280x720), SPP (8), TARGET (0.01), PAIR (0; 1: --pair),
# REUSE (1: keep the renders already in OUT and only re-measure), ERES (640x360), ESPP (256).
set -euo pipefail
cd "$(dirname "$0")/.."
out=${1:-build/shading_auto}
shift || true
plumage=$(realpath "${PLUMAGE:-build/plumage}")
res=${RES:-1280x720}
spp=${SPP:-8}
target=${TARGET:-0.01}
mkdir -p "$out"
export PLUMAGE_FARFIELD_CACHE=${PLUMAGE_FARFIELD_CACHE:-$(realpath "$out")/farfield-cache}
echo "machine: $(nproc) cores, $(lscpu | sed -n 's/^Model name: *//p'); load: $(cut -d' ' -f1-3 /proc/loadavg)"
pair=()
[ "${PAIR:-0}" = 1 ] && pair=(--pair)
"$plumage" -q wing -o "$out/wing.fscene" --seed 1 "${pair[@]}"
echo "fitting (or reading) the far-field tables..."
"$plumage" -q render "$out/wing.fscene" --shading farfield --spp 1 --resolution 1x1 -o "$out/fit.exr"

rms() { { idiff -a "$1" "$2" 2>/dev/null || true; } | sed -n 's/^ *RMS error = *\([0-9.eE+-]*\).*/\1/p'; }
for mode in substructure auto; do
  for seed in 1 2; do
    [ "${REUSE:-0}" = 1 ] && [ -f "$out/$mode.$seed.exr" ] && continue
    /usr/bin/time -f "%e %U %S %M" -o "$out/$mode.$seed.time" "$plumage" -q --stats render "$out/wing.fscene" \
      --shading "$mode" --spp "$spp" --resolution "$res" --seed "$seed" -o "$out/$mode.$seed.exr" "$@" \
      >"$out/$mode.$seed.stats" 2>&1
  done
  oiiotool "$out/$mode.1.exr" "$out/$mode.2.exr" --add --mulc 0.5 -o "$out/$mode.mean.exr"
done

printf "| mode | placements substructure / farfield | wall s | CPU s | peak RSS MiB | noise | CPU s to noise %s |\n|---|---|---|---|---|---|---|\n" "$target" \
  >"$out/table.md"
declare -A noise
for mode in substructure auto; do
  n=$(rms "$out/$mode.1.exr" "$out/$mode.2.exr")
  noise[$mode]=$n
  ns=$(sed -n 's/.*Placements shaded substructure *\([0-9]*\).*/\1/p' "$out/$mode.1.stats")
  nf=$(sed -n 's/.*Placements shaded farfield *\([0-9]*\).*/\1/p' "$out/$mode.1.stats")
  [ -z "$ns" ] && ns=all && nf=0
  cat "$out/$mode.1.time" "$out/$mode.2.time" | awk -v m="$mode" -v n="$n" -v t="$target" -v ns="$ns" -v nf="$nf" \
    '{ w += $1; c += $2 + $3; if ($4 > r) r = $4 } END {
       sigma = n / sqrt(2); cpu = c / 2;
       printf "| %s | %s / %s | %.1f | %.1f | %.0f | %.4f | %.0f |\n", m, ns, nf, w / 2, cpu, r / 1024, sigma, cpu * (sigma / t)^2 }' \
    >>"$out/table.md"
done
d=$(rms "$out/substructure.mean.exr" "$out/auto.mean.exr")
awk -v d="$d" -v a="${noise[auto]}" -v s="${noise[substructure]}" 'BEGIN {
  m = d * d - (a * a / 2 + s * s / 2) / 2;
  printf "\nRMS difference auto - substructure (two-seed means): %.4f; with the means'"'"' noise taken out: %s\n",
    d, (m > 0 ? sprintf("%.4f", sqrt(m)) : "within the noise") }' >>"$out/table.md"
echo "resolution $res, $spp spp, flags: $*" >>"$out/table.md"
cat "$out/table.md"

espp=${ESPP:-256}
eres=${ERES:-640x360}
[ "$espp" = 0 ] && exit 0
timed() {  # timed NAME render-args...: renders $out/NAME.exr unless reused; prints its CPU seconds
  local name=$1
  shift
  if ! { [ "${REUSE:-0}" = 1 ] && [ -f "$out/$name.exr" ]; }; then
    /usr/bin/time -f "%e %U %S %M" -o "$out/$name.time" "$plumage" -q render "$out/wing.fscene" --resolution "$eres" \
      -o "$out/$name.exr" "$@"
  fi
  awk '{ print $2 + $3 }' "$out/$name.time"
}
echo "explicit reference: $eres, $espp spp (minutes)..."
timed explicit.ref --shading explicit --spp "$espp" --seed 0 >/dev/null
timed explicit.64 --shading explicit --spp 64 --seed 2 >/dev/null
ref_noise=$(awk -v r="$(rms "$out/explicit.ref.exr" "$out/explicit.64.exr")" -v n="$espp" \
  'BEGIN { print sqrt(r * r / (1 + n / 64)) }')  # RMSE^2 = sigma_64^2 + sigma_ref^2, sigma_ref^2 = sigma_64^2 64 / n
{
  printf "\nAgainst an explicit reference (%s, %s spp; its own noise %.4f):\n\n" "$eres" "$espp" "$ref_noise"
  printf "| mode | RMSE at 4 / 16 / 64 spp | CPU s at 4 / 16 / 64 spp | model error |\n|---|---|---|---|\n"
} >>"$out/table.md"
for mode in substructure auto; do
  r=() c=()
  for n in 4 16 64; do
    c+=("$(timed "$mode.e$n" --shading "$mode" --spp "$n" --seed 1)")
    r+=("$(rms "$out/explicit.ref.exr" "$out/$mode.e$n.exr")")
  done
  awk -v m="$mode" -v r4="${r[0]}" -v r16="${r[1]}" -v r64="${r[2]}" -v c4="${c[0]}" -v c16="${c[1]}" -v c64="${c[2]}" \
    -v q="$ref_noise" 'BEGIN {
      s = (r16 * r16 - r64 * r64) / (1 / 16 - 1 / 64); m2 = r64 * r64 - s / 64 - q * q;
      printf "| %s | %.4f / %.4f / %.4f | %.1f / %.1f / %.1f | %s |\n", m, r4, r16, r64, c4, c16, c64,
        (m2 > 0 ? sprintf("%.4f", sqrt(m2)) : "within the noise") }' >>"$out/table.md"
done
cat "$out/table.md"
