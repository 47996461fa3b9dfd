#!/usr/bin/env bash
# Instancing measured (docs/scene-format.md, docs/perf/scene.md): a fan of PLACEMENTS
# feathers drawn from DISTINCT distinct ones (three presets, several seeds each),
# then the same scene with a mirrored copy of every placement beside it (twice the
# placements, no new feather: a pair of wings). Each is rendered once with
# `plumage --stats render` under /usr/bin/time; the table gives wall and CPU time,
# peak resident memory, and the scene's own counts.
# Usage: scripts/scene_scaling.sh [OUT] — environment: PLUMAGE (build/plumage),
# PLACEMENTS (48), DISTINCT (12), RES (1280x720), SPP (4), SHADING (hair).
set -euo pipefail
cd "$(dirname "$0")/.."
out=${1:-build/scene_scaling}
plumage=${PLUMAGE:-build/plumage}
n=${PLACEMENTS:-48}
k=${DISTINCT:-12}
res=${RES:-1280x720}
spp=${SPP:-4}
shading=${SHADING:-hair}
mkdir -p "$out"
echo "machine: $(nproc) cores, $(lscpu | sed -n 's/^Model name: *//p'); load: $(cut -d' ' -f1-3 /proc/loadavg)"

presets=(rock-dove-wing osprey-wing-covert turkey-vulture-back-covert)
write_scene() {  # FILE PAIRED(0|1)
  {
    echo "fscene 1"
    echo "units mm"
    for ((i = 0; i < k; ++i)); do echo "feather f$i preset ${presets[i % 3]} seed $((i + 1))"; done
    echo "lights 2-25"
    for ((j = 0; j < n; ++j)); do
      # A fan: feather j turned by up to +-60 degrees about its base, bases along an arc.
      local angle x y
      angle=$(awk -v j="$j" -v n="$n" 'BEGIN { printf "%.3f", -60 + 120 * j / (n > 1 ? n - 1 : 1) }')
      x=$(awk -v j="$j" -v n="$n" 'BEGIN { printf "%.3f", 1.5 * j }')
      y=$(awk -v j="$j" 'BEGIN { printf "%.3f", 0.5 * (j % 3) }')
      echo "place f$((j % k)) rotate 0 0 $angle translate $x $y $(awk -v j="$j" 'BEGIN { printf "%.2f", 0.05 * j }')"
      if [[ $2 == 1 ]]; then
        echo "place f$((j % k)) rotate 0 0 $angle translate $x $y $(awk -v j="$j" 'BEGIN { printf "%.2f", 0.05 * j }') mirror x translate -20 0 0"
      fi
    done
    echo "end"
  } >"$1"
}
write_scene "$out/one.fscene" 0
write_scene "$out/pair.fscene" 1

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
