#!/usr/bin/env bash
# The accuracy study of docs/substructure.md ("Explicit reference"): hair,
# substructure and far-field shading against an explicit-geometry reference of the
# same feather, view and lights, at a ladder of samples per pixel; then a picture
# of the zoomed view in the four modes. Writes into OUT (default build/explicit_study):
#   {zoom,full}_{one,all}.csv   mode,spp,seconds,rmse,relative_mse,cpu_seconds (vs explicit)
#   crops.png                   explicit | substructure | farfield | hair, zoomed
#   summary.md                  the tables, also spliced into docs/substructure.md
#   farfield_cache/             the far-field tables (PLUMAGE_FARFIELD_CACHE, unless set)
# Usage: scripts/explicit_study.sh [OUT] — environment: PLUMAGE (the binary),
# PRESET (rock-dove-wing), LED (the single LED, 10), REF_SPP (1024), SPP (1,4,16,64,256),
# MODES (hair,substructure,farfield,explicit; explicit gives the noise estimate).
set -euo pipefail
cd "$(dirname "$0")/.."
out=${1:-build/explicit_study}
plumage=${PLUMAGE:-build/plumage}
preset=${PRESET:-rock-dove-wing}
led=${LED:-10}
ref_spp=${REF_SPP:-1024}
spp=${SPP:-1,4,16,64,256}
zoom=${ZOOM:-10,60,0.6}
modes=${MODES:-hair,substructure,farfield,explicit}
mkdir -p "$out"
export PLUMAGE_FARFIELD_CACHE=${PLUMAGE_FARFIELD_CACHE-$out/farfield_cache}
echo "machine: $(nproc) cores, $(lscpu | sed -n 's/^Model name: *//p'); load: $(cut -d' ' -f1-3 /proc/loadavg)"

run() {  # NAME LIGHTS VIEW-ARGS...
  local name=$1 lights=$2
  shift 2
  echo "== $name (lights $lights) $*"
  /usr/bin/time -f "$name: %e s wall, %U s user, %M KB max RSS" \
    "$plumage" -q bench --preset "$preset" --modes "$modes" --reference-mode explicit \
    --reference-spp "$ref_spp" --spp "$spp" --lights "$lights" --csv "$out/$name.csv" --plot "$out/$name.png" "$@"
  cat "$out/$name.csv"
}
# Fit (or read) the far-field tables once, so that no rung's time includes a fit.
"$plumage" -q generate --preset "$preset" -o "$out/feather.fcurves"
/usr/bin/time -f "far-field fit: %e s wall, %U s user" "$plumage" -q render "$out/feather.fcurves" --shading farfield \
  --resolution 4x4 --spp 1 --stats -o "$out/fit.png" 2>&1 | grep -E 'Fit:|Tables|far-field fit'
run zoom_one "$led" --zoom "$zoom" --resolution 64x64
run zoom_all all --zoom "$zoom" --resolution 64x64
run full_one "$led" --resolution 48x72
run full_all all --resolution 48x72
# The tables of docs/substructure.md ("The study"): each ladder, and the model error
# (noise taken out) and CPU time per sample of every mode.
python3 scripts/explicit_summary.py "$out" "$ref_spp" >"$out/summary.md"
python3 scripts/doc_table.py docs/substructure.md explicit-study "$out/summary.md"

# The picture: the zoomed view in each mode (perspective top view of about the same
# area; 128x128, 256 spp), side by side: all LEDs over white paper on top, the single
# LED over black card (+2 stops) below.
IFS=, read -r zx zy zh <<<"$zoom"
height=$(awk -v h="$zh" 'BEGIN { print h / (2 * sin(15 * atan2(0, -1) / 180) / cos(15 * atan2(0, -1) / 180)) }')
for mode in explicit substructure farfield hair; do
  "$plumage" -q render "$out/feather.fcurves" --shading "$mode" --spp 256 --resolution 128x128 \
    --camera-pos "$zx,$zy,$height" --look-at "$zx,$zy,0" -o "$out/crop_$mode.png"
  "$plumage" -q render "$out/feather.fcurves" --shading "$mode" --spp 256 --resolution 128x128 \
    --lights "$led" --backdrop black --exposure 2 --camera-pos "$zx,$zy,$height" --look-at "$zx,$zy,0" \
    -o "$out/led_$mode.png"
done
oiiotool "$out/crop_explicit.png" "$out/crop_substructure.png" "$out/crop_farfield.png" "$out/crop_hair.png" \
  "$out/led_explicit.png" "$out/led_substructure.png" "$out/led_farfield.png" "$out/led_hair.png" \
  --mosaic:pad=4 4x2 -o "$out/crops.png"
echo "wrote $out/crops.png"
