#!/usr/bin/env bash
# Installs the Debian packages nbrdf needs to build, test and run (Debian bookworm).
# Run as root (or with sudo). Installs nothing when everything is already there.
set -euo pipefail

packages=(
  build-essential cmake ninja-build pkg-config clang
  libopenblas-dev libcjson-dev
  libopenexr-dev openexr
  libopenimageio-dev openimageio-tools
  libopencolorio-dev opencolorio-tools
  libtinygltf-dev
  glslang-tools libvulkan-dev mesa-vulkan-drivers vulkan-tools
  blender python3-numpy python3-openimageio
  # a one-node Slurm cluster for tests/farm (scripts/slurm-local.sh)
  slurm-wlm slurm-client munge
)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "setup: all ${#packages[@]} Debian packages present"
  exit 0
fi
if [ "$(id -u)" -ne 0 ]; then
  echo "setup: missing packages: ${missing[*]}; run this script as root" >&2
  exit 1
fi
echo "setup: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
apt-get update -qq
apt-get install -y -qq --no-install-recommends "${missing[@]}"
