#!/usr/bin/env bash
# Installs everything grainlab needs from Debian 12's packages. Non-interactive and
# idempotent: packages already present are skipped, so re-running is cheap.
set -euo pipefail

packages=(
  build-essential cmake ninja-build pkg-config git
  libeigen3-dev libhdf5-dev hdf5-tools libtomlplusplus-dev libcli11-dev libfmt-dev
  nlohmann-json3-dev libboost-dev libgtest-dev libgmock-dev googletest libbenchmark-dev
  libbox2d-dev libbullet-dev libbullet-extras-dev libode-dev libopenmpi-dev openmpi-bin
  python3-matplotlib python3-h5py python3-numpy
)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "setup: all ${#packages[@]} packages already installed"
  exit 0
fi

SUDO=""
[ "$(id -u)" -ne 0 ] && SUDO="sudo"
echo "setup: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
echo "setup: done"
