#!/usr/bin/env bash
# The installed plumage, away from the tree it was built from (docs/install.md):
#   1. `cmake --install` the build into a temporary prefix and `cpack` a .deb;
#   2. move the source tree (with its build folder) out of reach;
#   3. with the installed binary: --version names the commit, no --help shows a
#      path of the build machine, a preset renders, and photo-to-feather runs on
#      the pink photo (when ../shared holds it); the .deb holds the same files and
#      its unpacked binary runs too;
#   4. move the tree back (also on failure).
#   scripts/install_check.sh            uses build/ (scripts/test.sh builds it)
#   BUILD_DIR=... scripts/install_check.sh
set -euo pipefail
src=$(cd "$(dirname "$0")/.." && pwd)
build=$(cd "${BUILD_DIR:-$src/build}" && pwd)
tmp=$(mktemp -d)
fail() { echo "install_check: FAIL: $*" >&2; exit 1; }

cmake --install "$build" --prefix "$tmp/prefix" >/dev/null
(cd "$build" && cpack -G DEB -B "$tmp/deb" >/dev/null)
deb=$(ls "$tmp"/deb/plumage_*.deb)
dpkg-deb -x "$deb" "$tmp/unpacked"
photo="$src/../shared/photos/pink-contour-feather.jpg"
if [ -f "$photo" ]; then cp "$photo" "$tmp/pink.jpg"; fi  # a scratch copy, outside the project

# Out of reach: the whole tree if it can be renamed (it may be a mount point),
# else the two things a binary could find there, data/ and the build folder.
moved=()
restore() {
  local i
  for ((i = ${#moved[@]} - 1; i >= 0; i--)); do mv "${moved[i]}.away-$$" "${moved[i]}"; done
  rm -rf "$tmp"
}
trap restore EXIT
if mv "$src" "$src.away-$$" 2>/dev/null; then
  moved+=("$src")
else
  for d in "$src/data" "$build"; do mv "$d" "$d.away-$$" && moved+=("$d"); done
fi
cd "$tmp"

check_binary() {  # $1: an installed plumage
  local p=$1 out
  out=$("$p" --version)
  [[ $out =~ ^plumage\ [0-9]+\.[0-9]+\.[0-9]+\ \(commit\ ([0-9a-f]{12}\+?|unknown)\)$ ]] ||
    fail "$p --version printed '$out'"
  for c in "" analyze bench compare export generate info photo-to-feather render; do
    if "$p" $c --help | grep -F -e "$src" -e "$build"; then fail "$p $c --help shows a path of the build machine"; fi
  done
  "$p" generate --list-presets | grep -q rock-dove-wing || fail "$p finds no presets"
  "$p" -q generate --preset rock-dove-wing -o "$tmp/f.fcurves"
  "$p" -q render "$tmp/f.fcurves" --resolution 32x48 --spp 4 -o "$tmp/f.png"
  "$p" -q render "$tmp/f.fcurves" --resolution 32x48 --spp 4 -o "$tmp/f.tif"  # through the image module
  echo "install_check: $p: $out; presets, the dome, the image module found"
}

check_binary "$tmp/prefix/bin/plumage"
check_binary "$tmp/unpacked/usr/bin/plumage"
for f in usr/bin/plumage usr/lib/plumage/plumage_image_oiio.so usr/share/plumage/rigs/dome25.json \
         usr/share/plumage/presets/rock-dove-wing.json; do
  [ -f "$tmp/unpacked/$f" ] || fail "$(basename "$deb") lacks /$f"
done
echo "install_check: $(basename "$deb"): $(dpkg-deb -f "$deb" Depends | tr ',' '\n' | wc -l) dependencies"

if [ -f "$tmp/pink.jpg" ]; then
  start=$EPOCHREALTIME
  "$tmp/prefix/bin/plumage" -q photo-to-feather "$tmp/pink.jpg" -o "$tmp/p2f"
  for f in layout.json feather.fcurves comparison.png summary.json; do
    [ -s "$tmp/p2f/$f" ] || fail "photo-to-feather with the installed binary wrote no $f"
  done
  echo "install_check: photo-to-feather on the pink photo with the installed binary: $(awk "BEGIN { printf \"%.1f\", $EPOCHREALTIME - $start }") s"
else
  echo "install_check: ../shared/photos/pink-contour-feather.jpg absent: photo-to-feather skipped"
fi
echo "install_check: passed"
