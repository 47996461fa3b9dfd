#!/usr/bin/env bash
# Installs the Debian 12 packages Plumage needs to build, test and benchmark.
# Idempotent: installs only what is missing, and runs `apt-get update` only then.
set -euo pipefail

packages=(
  build-essential cmake pkg-config ninja-build
  dpkg-dev file  # cpack -G DEB (scripts/install_check.sh): dpkg-shlibdeps and ELF detection
  libembree-dev libtbb-dev
  libosd-dev
  libopencv-dev
  libopenimageio-dev openimageio-tools libopenexr-dev libpng-dev libjpeg62-turbo-dev
  libglm-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  libcli11-dev nlohmann-json3-dev
)

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "ok installed"; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "setup: all ${#packages[@]} packages present"
  exit 0
fi

echo "setup: installing ${missing[*]}"
sudo_cmd=()
if [ "$(id -u)" -ne 0 ]; then sudo_cmd=(sudo); fi
export DEBIAN_FRONTEND=noninteractive
"${sudo_cmd[@]}" apt-get update -qq
"${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}"
