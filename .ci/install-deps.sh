#!/usr/bin/env bash
# Installs the packages this project needs on Debian 12 (bookworm: ParaView 5.11, Embree 3) or
# Debian 13 (trixie: ParaView 5.13, Embree 4); does nothing when all are present.
# Shared by Plugin/sdf-pipeline and Testing/run-tests (see README.md).
set -euo pipefail

codename=$( . /etc/os-release 2>/dev/null && echo "${VERSION_CODENAME:-}" ) || codename=

# The same names on both releases (libembree-dev is Embree 3.13 on 12, 4.3 on 13).
packages=(
  cmake g++ make ccache
  paraview paraview-dev python3-paraview
  libembree-dev libtbb-dev libeigen3-dev libboost-graph-dev libnanoflann-dev
  libgtest-dev libbenchmark-dev
  # paraview-dev's CMake config needs these without declaring them (see docs)
  libutfcpp-dev libavformat-dev libavcodec-dev libavutil-dev libswscale-dev libopenmpi-dev
  liblzma-dev liblz4-dev libdouble-conversion-dev
  # rendering without a display; the GUI test grabs the window (Pillow over XCB)
  xvfb xauth python3-pil
)
expat_minimum=
case "$codename" in
  trixie)
    # ParaView 5.13 is built with Qt 6 and skips the plugin documentation step ("not supported
    # with Qt6"), so no Qt development package is needed; the Python wrapping needs the
    # Python headers, which Debian 13's paraview-dev no longer pulls in.
    packages+=(python3-dev)
    # Without the Qt SVG image plugin the GUI's toolbar icons are blank (GUI test's window).
    packages+=(qt6-svg-plugins)
    ;;
  *)
    # ParaView 5.11 (Debian 12): paraview_add_plugin needs Qt5 and Qt5Help, and the
    # documentation step /usr/lib/qt5/bin/xmlpatterns.
    packages+=(qtbase5-dev qttools5-dev qtxmlpatterns5-dev-tools)
    # Without the Qt SVG image plugin the GUI's toolbar icons are blank (GUI test's window).
    packages+=(libqt5svg5)
    # The OFF parser's libFuzzer target (Testing/run-fuzz-replay, run by Testing/run-tests on
    # Debian 12 only; Debian 13 names them clang-19 / libclang-rt-19-dev).
    packages+=(clang libclang-rt-14-dev)
    # Older than this libexpat1, ParaView 5.11 still reads raw appended XML data; a fresh
    # Debian 12 gets this version (a 2025 security update) and rejects it. Upgrade older
    # machines so that they see what a new user's machine sees (README, "Use from pvpython").
    expat_minimum=2.5.0-1+deb12u5
    ;;
esac

missing=()
for package in "${packages[@]}"; do
  status=$(dpkg-query -W -f='${Status}' "$package" 2>/dev/null || true)
  [[ "$status" == "install ok installed" ]] || missing+=("$package")
done
expat_version=$(dpkg-query -W -f='${Version}' libexpat1 2>/dev/null || true)
if [[ -n "$expat_minimum" && -n "$expat_version" ]] && dpkg --compare-versions "$expat_version" lt "$expat_minimum"; then
  missing+=(libexpat1)
fi
[[ ${#missing[@]} -eq 0 ]] && exit 0

echo "Installing missing or outdated packages: ${missing[*]}" >&2
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
# A mirror caught mid-sync fails some index files (seen: "File has unexpected size ... Mirror
# sync in progress?"); the lists already present usually still name the missing packages, and
# the install below fails clearly if they do not.
"${sudo_cmd[@]}" apt-get update -qq \
  || echo "warning: apt-get update failed (above); installing from the package lists already present" >&2
"${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
expat_version=$(dpkg-query -W -f='${Version}' libexpat1 2>/dev/null || true)
if [[ -n "$expat_minimum" && -n "$expat_version" ]] && dpkg --compare-versions "$expat_version" lt "$expat_minimum"; then
  echo "warning: libexpat1 $expat_version is older than $expat_minimum and no newer one is available" \
    "(are the security sources enabled?)" >&2
fi
