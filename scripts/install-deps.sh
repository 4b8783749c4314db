#!/usr/bin/env bash
# Installs every Debian 12 package that ldsm's build, tests, benchmarks and tools need.
# Idempotent and non-interactive; runs apt-get update itself. Needs root (or sudo).
set -euo pipefail

PACKAGES=(
  build-essential cmake ninja-build pkg-config ccache git
  libeigen3-dev
  libopencv-dev libopencv-contrib-dev
  libceres-dev libsuitesparse-dev
  libspdlog-dev libfmt-dev
  libyaml-cpp-dev libcli11-dev
  libzip-dev zipcmp zipmerge ziptool zlib1g-dev
  libpng-dev libjpeg62-turbo-dev
  libv4l-dev libcamera-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  libcivetweb-dev libjs-three chromium
  pybind11-dev python3-dev python3-numpy python3-pytest python3-matplotlib
)

SUDO=""
if [ "$(id -u)" -ne 0 ]; then
  if command -v sudo >/dev/null 2>&1; then SUDO="sudo"; else
    echo "install-deps.sh: needs root or sudo to install packages" >&2; exit 1; fi
fi

missing=()
for p in "${PACKAGES[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ "${#missing[@]}" -eq 0 ]; then
  echo "install-deps.sh: all ${#PACKAGES[@]} packages already installed"
  exit 0
fi
echo "install-deps.sh: installing ${#missing[@]} packages: ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
