#!/usr/bin/env bash
# The photo study (issue 11): `plumage analyze` and `plumage generate` on every photo
# in ../shared/photos; writes the overlays to docs/images/study-<photo>.jpg and a
# table (feathers by eye, regions found and expected from the named groups, analysed,
# skipped and why, rows cut by their quills, barbs per side, shaft length,
# warnings) into docs/analysis.md between the photo-study markers. The counts by eye
# are data/photo-study/counts.json (tests/photo_study_test.cpp holds analysis to them).
#   scripts/photo_study.sh            (needs a built build/plumage)
#   BUILD_DIR=... PHOTOS=... scripts/photo_study.sh
set -euo pipefail
cd "$(dirname "$0")/.."
build=${BUILD_DIR:-build}
photos=${PHOTOS:-../shared/photos}
[ -d "$photos" ] || { echo "photo_study.sh: no $photos" >&2; exit 1; }
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
for photo in "$photos"/*.jpg "$photos"/*.png; do
  [ -f "$photo" ] || continue
  name=$(basename "$photo"); stem=${name%.*}
  grid=$(python3 -c "import json,sys; p=json.load(open('data/photo-study/counts.json'))['photos'].get(sys.argv[1],{}); print(p.get('grid_mm',''))" "$name")
  opts=(); [ -n "$grid" ] && opts=(--grid-mm "$grid")
  start=$(date +%s.%N)
  rc=0
  "$build/plumage" analyze "$photo" -o "$out/$stem.json" --overlay "$out/$stem.png" "${opts[@]}" \
    2> "$out/$stem.analyze.txt" || rc=$?
  end=$(date +%s.%N)
  echo "$rc $(echo "$end - $start" | bc)" > "$out/$stem.rc"
  [ "$rc" = 0 ] || continue
  for id in $(python3 -c "import json,sys; print(' '.join(str(f['id']) for f in json.load(open(sys.argv[1]))['feathers']))" "$out/$stem.json"); do
    "$build/plumage" generate --layout "$out/$stem.json" --feather "$id" -o "$out/$stem.f$id.fcurves" \
      > "$out/$stem.f$id.gen.txt" 2>&1 || echo "generate failed: $?" >> "$out/$stem.f$id.gen.txt"
  done
  if command -v oiiotool > /dev/null; then
    width=$(oiiotool --info "$out/$stem.png" | sed -E 's/.*: +([0-9]+) x .*/\1/')
    resize=(); [ "$width" -gt 1000 ] && resize=(--resize 1000x0)
    oiiotool "$out/$stem.png" "${resize[@]}" --compression jpeg:80 -o "docs/images/study-$stem.jpg"
  elif command -v convert > /dev/null; then  # ImageMagick
    convert "$out/$stem.png" -resize '1000x>' -quality 80 "docs/images/study-$stem.jpg"
  else
    cp "$out/$stem.png" "docs/images/study-$stem.png"
  fi
done
python3 - "$out" "$photos" <<'PY'
import sys, os, json, glob, re, statistics
out, photos = sys.argv[1:3]
counts = json.load(open("data/photo-study/counts.json"))["photos"]
def expected(c):
    # counts.json's groups: k feathers making r regions each
    return c["feathers"] + sum(g["regions"] - g["feathers"] for g in c.get("groups", [])) if c.get("exact") else None
rows = ["| photo | by eye | regions (expected) | analysed | skipped (id: why) | rows cut by their quills (region: feathers) | barbs per side, median (range) | shaft length mm (range) | S-ness % median (max) | shafts ≥ 100 px over 1.5 % S-ness | seen as ridge % median (range) | warnings | analyze exit, wall s |",
        "|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
shaft_rows = []
for rc_file in sorted(glob.glob(os.path.join(out, "*.rc"))):
    stem = os.path.basename(rc_file)[:-3]
    name = next((n for n in counts if os.path.splitext(n)[0] == stem), stem)
    rc, wall = open(rc_file).read().split()
    eye = counts.get(name, {}).get("feathers", 0)
    rng = counts.get(name, {}).get("range")
    eye_text = (f"{eye} ({rng[0]}–{rng[1]})" if rng else str(eye)) if eye else "not counted"
    if rc != "0":
        err = open(os.path.join(out, stem + ".analyze.txt")).read().strip().splitlines()
        rows.append(f"| {name} | {eye_text} | — | — | — | — | — | — | — | — | — | {err[-1] if err else ''} | {rc}, {float(wall):.2f} |")
        continue
    L = json.load(open(os.path.join(out, stem + ".json")))
    kept = [s for s in L.get("skipped", []) if s["reason"] != "split_row"]
    skipped = ", ".join(f"{s['id']}: " + ("border" if s["reason"] == "touches_border"
                                          else "quills" if "quills side by side" in s["message"] else "touching")
                        for s in kept)
    # A shingled row cut along its quills: the region's id and its feathers' ids.
    split = []
    for s in L.get("skipped", []):
        if s["reason"] != "split_row": continue
        ids = [f["id"] for f in L["feathers"] if f.get("shingled_row", {}).get("region") == s["id"]]
        split.append(f"{s['id']}: " + ", ".join(f"F{i}" for i in ids))
    barbs, lengths, kinds = [], [], {}
    s_ness, seen, over = [], [], []
    arcs = counts.get(name, {}).get("shafts_not_simple_arcs", {})
    for f in L["feathers"]:
        lengths.append(f["shaft"]["length_mm"])
        s_ness.append(100 * f["shaft"]["s_ness"])
        seen.append(100 * f["shaft"]["seen_as_ridge"])
        length_px = f["shaft"]["length_mm"] / L["scale"]["mm_per_px"]
        if length_px >= 100 and s_ness[-1] > 1.5:
            why = arcs.get(f"F{f['id']}", "")  # counts.json: "no simple arc: ..." or "trace off: ..."
            over.append(f"F{f['id']} {s_ness[-1]:.1f}" + (f" ({why.split(':')[0]})" if why else ""))
        gen = open(os.path.join(out, f"{stem}.f{f['id']}.gen.txt")).read()
        m = re.search(r"\(left (\d+), right (\d+)[;)]", gen)
        if m: barbs += [int(m.group(1)), int(m.group(2))]
        for line in gen.splitlines():
            if "warning:" not in line: continue
            w = line.split(": ", 3)[-1]
            key = ("width: hidden in a row" if "shingled row" in w
                   else "downy base built loose" if "downy base" in w
                   else "plume built as down barbs" if "a plume" in w
                   else "spacing: prior" if "used the prior" in w else "spacing: other vane" if "vane's" in w
                   else "angle raised (fanning)" if "fan apart" in w
                   else "angle raised (vane widens)" if "raised where" in w else "angle held" if "held back" in w
                   else "angles < 15 deg ignored" if "below 15" in w else "angles > 90 deg ignored" if "above 90" in w
                   else "angle outliers ignored" if "off their neighbours" in w
                   else "barb bend reduced" if "barb bend" in w else "width narrowed" if "narrowed" in w
                   else "shaft bend reduced" if "shaft bend" in w else "no confident angle" if "no station is confident" in w
                   else "other")
            kinds[key] = kinds.get(key, 0) + 1
    b = f"{statistics.median(barbs):.0f} ({min(barbs)}–{max(barbs)})" if barbs else "—"
    l = f"{min(lengths):.0f}–{max(lengths):.0f}" if lengths else "—"
    warn = "; ".join(f"{k} ×{v}" for k, v in sorted(kinds.items(), key=lambda kv: -kv[1]))
    exp = expected(counts.get(name, {}))
    found = len(L["feathers"]) + len(kept)  # a row cut by its quills counts as its feathers
    regions = f"{found} ({exp})" if exp is not None else str(found)
    sn = f"{statistics.median(s_ness):.1f} ({max(s_ness):.1f})" if s_ness else "—"
    sr = f"{statistics.median(seen):.0f} ({min(seen):.0f}–{max(seen):.0f})" if seen else "—"
    rows.append(f"| {name} | {eye_text} | {regions} | {len(L['feathers'])} | {skipped or '—'} | {'; '.join(split) or '—'} | {b} | {l} | {sn} | {', '.join(over) or '—'} | {sr} | {warn or '—'} | {rc}, {float(wall):.2f} |")
open(os.path.join(out, "photo-study-table.md"), "w").write("\n".join(rows) + "\n")
PY
python3 scripts/doc_table.py docs/analysis.md photo-study "$out/photo-study-table.md"
echo "photo_study.sh: table in docs/analysis.md, overlays in docs/images/study-*.jpg"
