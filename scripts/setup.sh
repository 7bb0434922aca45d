#!/usr/bin/env bash
# Installs every Debian package prw needs. Idempotent: packages already present are skipped,
# and apt is not touched at all when nothing is missing.
set -euo pipefail
PKGS=(
  build-essential cmake pkg-config git
  mesa-vulkan-drivers libvulkan-dev vulkan-validationlayers vulkan-tools glslang-tools spirv-tools
  libglfw3-dev libopenexr-dev libpng-dev zlib1g-dev libtinygltf-dev libdraco-dev nlohmann-json3-dev libstb-dev libcjson-dev
  libkissfft-dev
  libembree-dev libtbb-dev
  xvfb xauth
  slurm-wlm munge
  clang libclang-rt-14-dev
  libglu1-mesa-dev
  python3-skimage
  gnuplot-nox
)
missing=()
for p in "${PKGS[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "setup: all ${#PKGS[@]} packages present"
  exit 0
fi
SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
echo "setup: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
echo "setup: done"
