#!/usr/bin/env bash
# Installs the Debian 12 packages this project needs; does nothing when all are present.
# Shared by Plugin/sdf-pipeline and Testing/run-tests (see README.md).
set -euo pipefail

packages=(
  cmake g++ make ccache
  paraview paraview-dev python3-paraview
  libembree-dev libtbb-dev libeigen3-dev libboost-graph-dev libnanoflann-dev
  libgtest-dev libbenchmark-dev
  # paraview-dev's CMake config needs these without declaring them (see docs)
  libutfcpp-dev libavformat-dev libavcodec-dev libavutil-dev libswscale-dev libopenmpi-dev
  liblzma-dev liblz4-dev libdouble-conversion-dev qtbase5-dev qttools5-dev qtxmlpatterns5-dev-tools
  # rendering without a display
  xvfb xauth
)

missing=()
for package in "${packages[@]}"; do
  status=$(dpkg-query -W -f='${Status}' "$package" 2>/dev/null || true)
  [[ "$status" == "install ok installed" ]] || missing+=("$package")
done
[[ ${#missing[@]} -eq 0 ]] && exit 0

echo "Installing missing packages: ${missing[*]}" >&2
sudo_cmd=()
if [[ $(id -u) -ne 0 ]]; then
  if command -v sudo >/dev/null; then
    sudo_cmd=(sudo)
  else
    echo "error: missing packages (${missing[*]}) and not root; install them with apt-get" >&2
    exit 1
  fi
fi
export DEBIAN_FRONTEND=noninteractive
"${sudo_cmd[@]}" apt-get update -qq
"${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
