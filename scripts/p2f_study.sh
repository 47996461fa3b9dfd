#!/usr/bin/env bash
# The photo-to-feather fidelity study (issue 12): `plumage photo-to-feather` at its
# defaults on feathers picked across every photo in ../shared/photos (the single
# pink feather and feathers from each sheet). Writes the fidelity table (silhouette
# IoU, CIE dE2000, luminance correlation and perimeter ratio per render panel, whole
# feather and per vane; the share of texels given a medulla; timings) into
# docs/analysis.md between the p2f-study markers, the comparisons as downscaled
# JPEGs to docs/images/p2f-<photo>-f<K>.jpg, and, for the pink photo, the render
# noise (a second run with --seed 2; the generated feather does not depend on the
# seed, the renders' samples do). Metrics: docs/analysis.md, "Fidelity".
#   scripts/p2f_study.sh            (needs a built build/plumage and oiiotool)
#   BUILD_DIR=... PHOTOS=... THREADS=2 scripts/p2f_study.sh
set -euo pipefail
cd "$(dirname "$0")/.."
build=${BUILD_DIR:-build}
photos=${PHOTOS:-../shared/photos}
threads=${THREADS:-2}
[ -d "$photos" ] || { echo "p2f_study.sh: no $photos" >&2; exit 1; }
command -v oiiotool > /dev/null || { echo "p2f_study.sh: needs oiiotool" >&2; exit 1; }
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT

# photo, feather id (0: a single-feather photo), why this one.
cases=(
  "pink-contour-feather.jpg 0 single contour feather on white"
  "spoonbill-wing-sheet.png 3 wing feather on black, grid"
  "spoonbill-wing-sheet.png 5 wing feather on black, grid"
  "blue-jay-feather-sheet.jpg 9 top tail feather, lying across"
  "blue-jay-feather-sheet.jpg 12 small body feather"
  "blue-jay-feather-sheet.jpg 41 tail feather, upright"
  "european-goldfinch-feather-sheet.jpg 19 single feather at the right of the bottom row"
  "european-robin-feather-sheet.jpg 14 upright body feather"
  "european-robin-feather-sheet.jpg 41 upright body feather"
  "peregrine-falcon-feather-sheet.jpg 13 largest on the sheet"
  "peregrine-falcon-feather-sheet.jpg 10 from the same row"
  "blue-jay-feather-sheet.jpg 15 white downy feather on the grey card"
  "blue-jay-feather-sheet.jpg 26 white downy plume on the grey card"
)

grid_of() {
  python3 -c "import json,sys; p=json.load(open('data/photo-study/counts.json'))['photos'].get(sys.argv[1],{}); print(p.get('grid_mm',''))" "$1"
}

for c in "${cases[@]}"; do
  read -r name id why <<< "$c"
  stem=${name%.*}
  tag="$stem-f$id"; [ "$id" = 0 ] && tag="$stem"
  opts=(--threads "$threads")
  [ "$id" != 0 ] && opts+=(--feather "$id")
  grid=$(grid_of "$name"); [ -n "$grid" ] && opts+=(--grid-mm "$grid")
  echo "p2f_study.sh: $tag" >&2
  rc=0
  /usr/bin/time -f "%e %U %S" -o "$out/$tag.time" \
    "$build/plumage" photo-to-feather "$photos/$name" -o "$out/$tag" "${opts[@]}" > "$out/$tag.log" 2>&1 || rc=$?
  echo "$rc" > "$out/$tag.rc"
  echo "$why" > "$out/$tag.why"
  [ "$rc" = 0 ] || continue
  width=$(oiiotool --info "$out/$tag/comparison.png" | sed -E 's/.*: +([0-9]+) x .*/\1/')
  resize=(); [ "$width" -gt 1200 ] && resize=(--resize 1200x0)
  oiiotool "$out/$tag/comparison.png" "${resize[@]}" --compression jpeg:85 -o "docs/images/p2f-$tag.jpg"
done

# Render noise on the pink photo: the same command with --seed 2.
pink=pink-contour-feather
if [ -f "$out/$pink/summary.json" ]; then
  "$build/plumage" -q photo-to-feather "$photos/$pink.jpg" -o "$out/$pink-seed2" --threads "$threads" --seed 2 \
    2> "$out/seed2.log"
  oiiotool --diff "$out/$pink/comparison.png" "$out/$pink-seed2/comparison.png" > "$out/noise.txt" 2>&1 || true
fi

python3 - "$out" "$(nproc)" "$(cat /proc/loadavg)" <<'PY'
import sys, os, json, glob, re, math
out, cores, load = sys.argv[1], sys.argv[2], sys.argv[3]
rows = ["| photo, feather | why | panel px | silhouette IoU hair (L / R) | silhouette IoU substructure (L / R) | colour ΔE00 hair (L / R) | colour ΔE00 substructure (L / R) | pixel ΔE00 hair / substructure | luminance correlation hair / substructure | perimeter ratio hair / substructure | texels with a medulla hair / substructure | card ΔE00 hair / substructure | wall s, CPU s |",
        "|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
for rc_file in sorted(glob.glob(os.path.join(out, "*.rc"))):
    tag = os.path.basename(rc_file)[:-3]
    why = open(os.path.join(out, tag + ".why")).read().strip()
    rc = open(rc_file).read().strip()
    m = re.match(r"(.*)-f(\d+)$", tag)
    label = f"{m.group(1)}, {m.group(2)}" if m else f"{tag}, 1 (single)"
    if rc != "0":
        log = open(os.path.join(out, tag + ".log")).read().strip().splitlines()
        rows.append(f"| {label} | {why} | — | — | — | — | — | — | — | — | — | — | exit {rc}: {log[-1] if log else ''} |")
        continue
    s = json.load(open(os.path.join(out, tag, "summary.json")))
    f = s["fidelity"]
    wall, user, sys_ = (float(x) for x in open(os.path.join(out, tag + ".time")).read().split()[-3:])
    def tri(panel, key, fmt):
        p = f[panel]
        return f"{fmt.format(p['feather'][key])} ({fmt.format(p['left'][key])} / {fmt.format(p['right'][key])})"
    h, b = f["hair"], f["substructure"]
    def medulla(p):
        n = p.get("inversion")
        return f"{100.0 * n['medulla'] / n['texels']:.0f} %" if n and n["texels"] else "—"
    rows.append(f"| {label} | {why} | {f['panel']['width']}×{f['panel']['height']} | {tri('hair', 'silhouette_iou', '{:.3f}')} | "
                f"{tri('substructure', 'silhouette_iou', '{:.3f}')} | {tri('hair', 'mean_colour_de2000', '{:.1f}')} | "
                f"{tri('substructure', 'mean_colour_de2000', '{:.1f}')} | {h['feather']['pixel_de2000']:.1f} / {b['feather']['pixel_de2000']:.1f} | "
                f"{h['feather']['luminance_correlation']:.2f} / {b['feather']['luminance_correlation']:.2f} | "
                f"{h['perimeter_ratio']:.2f} / {b['perimeter_ratio']:.2f} | {medulla(h)} / {medulla(b)} | "
                f"{h['backdrop_de2000']:.1f} / {b['backdrop_de2000']:.1f} | {wall:.1f}, {user + sys_:.1f} |")
text = "\n".join(rows) + "\n"
noise = os.path.join(out, "noise.txt")
pink = os.path.join(out, "pink-contour-feather", "summary.json")
if os.path.exists(noise) and os.path.exists(pink):
    d = open(noise).read()
    rms = re.search(r"RMS error = ([0-9.eE+-]+)", d)
    s = json.load(open(pink))
    w, h = s["fidelity"]["panel"]["width"], s["fidelity"]["panel"]["height"]
    info = os.popen(f"oiiotool --info {os.path.join(out, 'pink-contour-feather', 'comparison.png')}").read()
    W, H = (int(x) for x in re.search(r"(\d+)\s*x\s*(\d+)", info).groups())
    if rms:
        # The photo panel, labels and gaps are the same in both runs: the difference is in the two render panels only.
        render_rms = float(rms.group(1)) * math.sqrt(W * H / (2.0 * w * h))
        text += (f"\nRender noise on the pink photo at the defaults ({s['render']['spp']} spp, {w}×{h} panels): "
                 f"σ = {render_rms / math.sqrt(2):.3f} per pixel and channel (sRGB values in [0, 1]; RMS over both "
                 f"render panels of the difference between --seed 1 and --seed 2, divided by √2).\n")
text += f"\nMachine: {cores} cores, load average {' '.join(load.split()[:3])} when the table was written.\n"
open(os.path.join(out, "p2f-study-table.md"), "w").write(text)
PY
python3 scripts/doc_table.py docs/analysis.md p2f-study "$out/p2f-study-table.md"
echo "p2f_study.sh: table in docs/analysis.md, comparisons in docs/images/p2f-*.jpg"
