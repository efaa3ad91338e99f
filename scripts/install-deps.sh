#!/usr/bin/env bash
# Installs every system dependency of owval from Debian 12 packages. Idempotent: apt-get skips
# what is already installed, and nothing is fetched when all packages are present.
set -euo pipefail
packages=(
  build-essential cmake ninja-build pkg-config git
  libeigen3-dev libhdf5-dev nlohmann-json3-dev libcli11-dev
  libgtest-dev libgmock-dev libbenchmark-dev libceres-dev libomp-dev
  libavcodec-dev libavformat-dev libavutil-dev libswscale-dev libx264-dev ffmpeg
  libosmesa6-dev libfreetype-dev fonts-dejavu-core libpng-dev
  clang-format
  libssl-dev  # libcrypto: SHA-256 of run-cache keys (backends/)
  python3-zarr python3-jsonschema  # tests only: WCON schema checks, OME-Zarr read back
)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#packages[@]} packages present"
  exit 0
fi
SUDO=""
[ "$(id -u)" -eq 0 ] || SUDO="sudo"
echo "install-deps: installing ${missing[*]}"
$SUDO env DEBIAN_FRONTEND=noninteractive apt-get update -qq
$SUDO env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends "${missing[@]}"
