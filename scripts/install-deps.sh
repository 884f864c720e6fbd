#!/usr/bin/env bash
# Installs the Debian packages brdffit builds, tests and runs with. Safe to run twice: when every
# package is already there it only checks (no apt-get update, no network).
set -euo pipefail
packages=(
  cmake g++ make pkg-config xz-utils
  libceres-dev libeigen3-dev libopenimageio-dev libopencv-dev
  libcli11-dev nlohmann-json3-dev libfmt-dev libgtest-dev libssl-dev
  openimageio-tools  # OpenImageIO's CMake package refers to its tools (iconvert, ...)
  pybind11-dev python3-dev python3-numpy python3-pytest python3-matplotlib  # the Python module, its tests, examples/
)
[[ "${BRDFFIT_WITH_CHROMIUM:-0}" == 1 ]] && packages+=(chromium)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  echo "install-deps: installing ${missing[*]}"
  sudo_cmd=()
  [[ $(id -u) -ne 0 ]] && sudo_cmd=(sudo)
  "${sudo_cmd[@]}" apt-get update -qq
  DEBIAN_FRONTEND=noninteractive "${sudo_cmd[@]}" apt-get install -y -q --no-install-recommends "${missing[@]}"
fi
