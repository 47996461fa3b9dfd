#!/usr/bin/env bash
# The main job on a built-in default: installs what is missing, builds, generates
# a preset feather, renders it with hair and substructure shading side by side,
# renders a pair of rock-dove wings (plumage wing --pair) beside it, and says where
# everything went.
#   scripts/demo.sh                  the Osprey wing covert preset
#   PRESET=rock-dove-wing scripts/demo.sh
#   scripts/demo.sh PHOTO            photo-to-feather on PHOTO (MM_PER_PX=0.08 SPP=32 optional)
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
build=${BUILD_DIR:-build}
cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$build" -j "$(nproc)" --target plumage
plumage="$build/plumage"
out=${OUT_DIR:-out}
mkdir -p "$out"

if [ $# -ge 1 ]; then
  if "$plumage" --help | grep -q photo-to-feather; then
    "$plumage" photo-to-feather "$1" -o "$out" --spp "${SPP:-16}" ${MM_PER_PX:+--mm-per-px "$MM_PER_PX"}
    echo "demo: wrote the photo-to-feather results to $out/ (comparison.png: photo | hair | substructure)"
    exit 0
  fi
  echo "demo: photo-to-feather is not implemented yet (issue 6); running the preset instead" >&2
fi

preset=${PRESET:-osprey-wing-covert}
"$plumage" generate --preset "$preset" --seed 1 -o "$out/feather.fcurves" --preview "$out/preview.png"
"$plumage" info "$out/feather.fcurves"
if "$plumage" --help | grep -q "compare"; then
  # Hair and substructure shading side by side: same camera, dome LEDs, samples, exposure.
  "$plumage" compare "$out/feather.fcurves" --spp ${SPP:-32} -o "$out/side_by_side.png"
  # A pair of wings, each distinct feather built once and placed twice (docs/wing.md).
  "$plumage" -q wing -o "$out/wing.fscene" --pair
  "$plumage" info "$out/wing.fscene" | head -1
  "$plumage" render "$out/wing.fscene" --spp ${SPP:-16} --resolution 960x540 -o "$out/wing.png"
  echo "demo: wrote $out/feather.fcurves, $out/preview.png, the side-by-side $out/side_by_side.png and the pair of wings $out/wing.png"
elif "$plumage" --help | grep -q "render"; then
  "$plumage" render "$out/feather.fcurves" --shading hair --lights all --spp ${SPP:-16} -o "$out/hair.png"
  echo "demo: wrote $out/feather.fcurves, $out/preview.png and $out/hair.png"
else
  echo "demo: wrote $out/feather.fcurves and $out/preview.png"
fi
