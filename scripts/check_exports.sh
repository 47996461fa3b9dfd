#!/usr/bin/env bash
# Checks that `plumage export --format pbrt-v3` renders in pbrt-v3 what `plumage
# render` renders (docs/exporters.md, "Checked against pbrt-v3"). Not part of the
# test suite: it needs pbrt-v3, which it builds from source outside the project.
#
#   scripts/check_exports.sh [BUILD_DIR]      (BUILD_DIR: plumage's build, default build)
#
# Environment:
#   PBRT_V3_GIT   bare git dir of github:mmp/pbrt-v3 (default /work/.mirror/mmp+pbrt-v3/repo)
#   PTEX_GIT      bare git dir of github:wdas/ptex   (default /work/.mirror/wdas+ptex/repo)
#   PEERS         where pbrt-v3 is unpacked and built (default /work/peers); the
#                 binary ends up at $PEERS/pbrt-v3/build/pbrt
#   OUT           where the scenes and images go (default /tmp/plumage_check_exports)
#   SPP, RES      samples per pixel (default 64) and image size (default 256x384)
#
# pbrt-v3 is built against Debian's OpenEXR, glog and zlib (their -dev packages are
# installed with apt-get when missing) and the ptex commit pbrt-v3 pins; its
# CMakeLists is edited in the unpacked copy to find those libraries. Prints a
# table of feather-pixel means and RMSE; exits 1 when the 2 x radius export is not
# within 3 % of plumage on feather pixels.
set -euo pipefail

ROOT=$(cd "$(dirname "$0")/.." && pwd)
BUILD=${1:-$ROOT/build}
PBRT_V3_GIT=${PBRT_V3_GIT:-/work/.mirror/mmp+pbrt-v3/repo}
PTEX_GIT=${PTEX_GIT:-/work/.mirror/wdas+ptex/repo}
PEERS=${PEERS:-/work/peers}
OUT=${OUT:-/tmp/plumage_check_exports}
SPP=${SPP:-64}
RES=${RES:-256x384}
JOBS=${JOBS:-2}
PBRT_SRC=$PEERS/pbrt-v3
PBRT=$PBRT_SRC/build/pbrt

fail() { echo "check_exports: error: $*" >&2; exit 1; }

build_pbrt_v3() {
  [ -x "$PBRT" ] && return 0
  for g in "$PBRT_V3_GIT" "$PTEX_GIT"; do
    git --git-dir="$g" rev-parse HEAD >/dev/null 2>&1 || fail "$g is not a git directory; fetch github:mmp/pbrt-v3 and github:wdas/ptex first"
  done
  local missing=()
  for p in libopenexr-dev libgoogle-glog-dev zlib1g-dev cmake bison flex; do
    dpkg -s "$p" >/dev/null 2>&1 || missing+=("$p")
  done
  if [ ${#missing[@]} -gt 0 ]; then
    echo "installing ${missing[*]}" >&2
    apt-get install -y "${missing[@]}" >&2
  fi
  mkdir -p "$PBRT_SRC"
  if [ ! -f "$PBRT_SRC/CMakeLists.txt" ]; then
    git --git-dir="$PBRT_V3_GIT" archive HEAD | tar -x -C "$PBRT_SRC"
    local ptex_commit
    ptex_commit=$(git --git-dir="$PBRT_V3_GIT" ls-tree HEAD src/ext/ptex | awk '{print $3}')
    mkdir -p "$PBRT_SRC/src/ext/ptex"
    git --git-dir="$PTEX_GIT" archive "$ptex_commit" | tar -x -C "$PBRT_SRC/src/ext/ptex"
    use_debian_libraries "$PBRT_SRC/CMakeLists.txt"
  fi
  cmake -S "$PBRT_SRC" -B "$PBRT_SRC/build" -DCMAKE_BUILD_TYPE=Release >&2
  nice cmake --build "$PBRT_SRC/build" -j"$JOBS" --target pbrt_exe >&2
  [ -x "$PBRT" ] || fail "the pbrt-v3 build did not produce $PBRT"
}

# pbrt-v3 builds OpenEXR, glog and zlib from git submodules; point it at
# Debian's instead (OpenEXR 3 keeps the Imf API pbrt-v3 uses).
use_debian_libraries() {
  local f=$1
  python3 - "$f" <<'EOF'
import re, sys
path = sys.argv[1]
s = open(path).read()
# The submodule checks for the three libraries taken from Debian.
for lib in ("openexr/OpenEXR", "glog/cmake", "zlib/doc"):
    s = re.sub(r'if\(NOT IS_DIRECTORY "\$\{CMAKE_CURRENT_SOURCE_DIR\}/src/ext/%s"\).*?endif\(\)\n' % re.escape(lib),
               "", s, flags=re.S)
s = s.replace("-std=gnu++11", "-std=gnu++14")
exr = re.search(r"SET\(ILMBASE_NAMESPACE_VERSIONING.*?ENDIF\(\)\n", s, flags=re.S)
s = s[:exr.start()] + ("FIND_PACKAGE(OpenEXR CONFIG REQUIRED)\n"
                       "INCLUDE_DIRECTORIES(/usr/include/OpenEXR /usr/include/Imath)\n"
                       "SET(OPENEXR_LIBS OpenEXR::OpenEXR)\n") + s[exr.end():]
glog = re.search(r"SET\(WITH_GFLAGS.*?\$\{CMAKE_BINARY_DIR\}/src/ext/glog\n\)\n", s, flags=re.S)
s = s[:glog.start()] + "FIND_PACKAGE(glog CONFIG REQUIRED)\n" + s[glog.end():]
s = s.replace("  glog\n  Ptex_static", "  glog::glog\n  Ptex_static")
open(path, "w").write(s)
EOF
}

# Images are compared with Debian's numpy and OpenImageIO bindings (the system python).
PY=/usr/bin/python3
need_python_modules() {
  "$PY" -c "import numpy, OpenImageIO" 2>/dev/null && return 0
  echo "installing python3-numpy python3-openimageio" >&2
  apt-get install -y python3-numpy python3-openimageio >&2
}

PLUMAGE=$BUILD/plumage
[ -x "$PLUMAGE" ] || fail "no $PLUMAGE: build plumage first (cmake --build $BUILD --target plumage)"
build_pbrt_v3
need_python_modules
echo "pbrt-v3: $PBRT" >&2
mkdir -p "$OUT"
cd "$OUT"
"$PLUMAGE" -q generate --preset rock-dove-wing --seed 1 -o dove.fcurves

# One view rendered by plumage and by pbrt-v3 from `plumage export`, plus a mask
# of the pixels whose camera rays hit the feather (the environment seen through
# a feather with no lights, no card and no scattering: 0 where every ray hits it).
# render_case NAME "WIDTH FLAGS" "LIGHT FLAGS"
render_case() {
  local name=$1
  local -a width lights
  read -r -a width <<<"$2"
  read -r -a lights <<<"$3"
  local view=(--resolution "$RES" --spp "$SPP" "${width[@]}")
  echo "$name: plumage render ${view[*]} ${lights[*]}" >&2
  "$PLUMAGE" -q render dove.fcurves -o "$name.plumage.exr" "${view[@]}" "${lights[@]}" --threads "$JOBS"
  "$PLUMAGE" -q render dove.fcurves -o "$name.mask.exr" "${view[@]}" --threads "$JOBS" \
    --lights none --backdrop none --env 1 --max-depth 0
  "$PLUMAGE" -q export dove.fcurves --format pbrt-v3 -o "$name.pbrt" "${view[@]}" "${lights[@]}"
  "$PBRT" --quiet --nthreads "$JOBS" --outfile "$name.pbrt-v3.exr" "$name.pbrt"
}

render_case dome_2r "--ribbon-width 0" ""
render_case dome_W "" ""
render_case sky_2r "--ribbon-width 0" "--lights none --backdrop none --env 1"
render_case sky_W "" "--lights none --backdrop none --env 1"

if command -v blender >/dev/null; then
  "$PLUMAGE" -q export dove.fcurves --format blender -o dome_W.py --resolution "$RES" --spp "$SPP"
  blender -b --factory-startup -P dome_W.py -o "$OUT/dome_W.blender_" -F OPEN_EXR -f 1 >blender.log 2>&1 ||
    fail "blender failed on dome_W.py: see $OUT/blender.log"
  mv dome_W.blender_0001.exr dome_W.blender.exr
  grep -o "plumage: built .*" blender.log >&2 || fail "dome_W.py built nothing: see $OUT/blender.log"
else
  echo "blender is not installed: its export is not rendered" >&2
fi

# Feather pixels: some camera ray in the pixel hits a fibre (mask below 0.98);
# covered pixels: every ray does (mask below 0.01). Means over RGB; RMSE over
# channel values; difference = target mean / plumage mean - 1.
"$PY" - <<'PYEOF'
import os, sys
import numpy as np
import OpenImageIO as oiio

def load(path):
    inp = oiio.ImageInput.open(path)
    if inp is None:
        sys.exit("check_exports: error: cannot read " + path)
    pixels = np.asarray(inp.read_image(format="float"))[..., :3]
    inp.close()
    return pixels

print("| view | width | renderer | pixels | plumage mean | target mean | difference | RMSE |")
print("|---|---|---|---|---|---|---|---|")
worst_2r = 0.0
cases = [("dome_2r", "pbrt-v3"), ("dome_W", "pbrt-v3"), ("sky_2r", "pbrt-v3"), ("sky_W", "pbrt-v3")]
if os.path.exists("dome_W.blender.exr"):
    cases.append(("dome_W", "blender"))
for name, target in cases:
    ref, mask = load(name + ".plumage.exr"), load(name + ".mask.exr").mean(axis=2)
    img = load(name + "." + target + ".exr")
    view, width = name.split("_")
    for label, sel in (("feather", mask < 0.98), ("covered", mask < 0.01)):
        a, b = ref[sel], img[sel]
        diff = b.mean() / a.mean() - 1
        rmse = np.sqrt(((b - a) ** 2).mean())
        print(f"| {view} | {width} | {target} | {label} ({sel.sum()}) | {a.mean():.4f} | {b.mean():.4f} | {100 * diff:+.1f} % | {rmse:.4f} |")
        if width == "2r" and label == "feather" and target == "pbrt-v3":
            worst_2r = max(worst_2r, abs(diff))
print()
if worst_2r > 0.03:
    print(f"FAIL: the 2r export differs from plumage by {100 * worst_2r:.1f} % on feather pixels (bound 3 %)")
    sys.exit(1)
print(f"OK: the 2r export is within {100 * worst_2r:.1f} % of plumage on feather pixels (bound 3 %)")
PYEOF
