#!/usr/bin/env bash
# Instancing measured (docs/scene-format.md, docs/perf/scene.md): the rock-dove wing
# of `plumage wing` (53 distinct feathers), then the pair (--pair: twice the
# placements, no new feather). Each is rendered once with `plumage --stats render`
# under /usr/bin/time; the table gives wall and CPU time, peak resident memory, and
# the scene's own counts.
# Usage: scripts/scene_scaling.sh [OUT] — environment: PLUMAGE (build/plumage),
# RES (1280x720), SPP (4), SHADING (hair; or substructure, farfield).
set -euo pipefail
cd "$(dirname "$0")/.."
out=${1:-build/scene_scaling}
plumage=${PLUMAGE:-build/plumage}
res=${RES:-1280x720}
spp=${SPP:-4}
shading=${SHADING:-hair}
mkdir -p "$out"
echo "machine: $(nproc) cores, $(lscpu | sed -n 's/^Model name: *//p'); load: $(cut -d' ' -f1-3 /proc/loadavg)"

"$plumage" -q wing -o "$out/one.fscene" --seed 1
"$plumage" -q wing -o "$out/pair.fscene" --seed 1 --pair

printf "| scene | placements | distinct | barbs over all placements | wall s | CPU s | peak RSS MiB |\n|---|---|---|---|---|---|---|\n" >"$out/table.md"
for s in one pair; do
  /usr/bin/time -f "%e %U %S %M" -o "$out/$s.time" "$plumage" -q --stats render "$out/$s.fscene" -o "$out/$s.png" \
    --resolution "$res" --spp "$spp" --shading "$shading" >"$out/$s.stats" 2>&1
  read -r wall user sys rss <"$out/$s.time"
  info=$("$plumage" info "$out/$s.fscene" --json)
  p=$(echo "$info" | python3 -c 'import json,sys; j=json.load(sys.stdin); print(j["placements"], j["distinct_feathers"], j["barbs"])')
  read -r pl di ba <<<"$p"
  awk -v s="$s" -v pl="$pl" -v di="$di" -v ba="$ba" -v w="$wall" -v u="$user" -v y="$sys" -v r="$rss" \
    'BEGIN { printf "| %s | %s | %s | %s | %s | %.1f | %.0f |\n", s, pl, di, ba, w, u + y, r / 1024 }' >>"$out/table.md"
done
cat "$out/table.md"
echo "images: $out/one.png $out/pair.png"
