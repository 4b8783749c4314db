#!/usr/bin/env bash
# Prepares everything an ldsm cross build for ARM needs on a Debian 12 (bookworm) x86-64 machine:
#   * host packages (apt): the cross compilers (crossbuild-essential-arm64 / -armhf), qemu-user-static,
#     mmdebstrap, cmake, ninja, pkg-config, ccache;
#   * a target sysroot made of Debian bookworm arm64 / armhf packages: every library ldsm links
#     (OpenCV, Ceres + SuiteSparse, yaml-cpp, libzip, libpng, libjpeg, spdlog, Eigen, GoogleTest,
#     CLI11, V4L2, libcamera). Debian multiarch cannot co-install the arm64 OpenCV and Ceres -dev
#     packages next to the host's, hence the separate tree.
#
#   toolchains/prepare-sysroot.sh aarch64|armhf [--no-apt]
#
# The sysroot lives OUTSIDE the repository, in ${LDSM_CROSS_CACHE:-$HOME/.cache/ldsm-cross}/<arch>.
# It is made once (about a minute and 1.2 GB, mostly downloads) and reused while its stamp matches
# this script's package list; delete the folder to rebuild it. Prints the sysroot path last.
#
# How: `mmdebstrap --variant=extract` downloads the packages with their dependencies and unpacks
# them without running any maintainer script (no emulation needed, works in containers). What the
# scripts would have done and the build needs is redone here: absolute symlinks are made relative
# (so they resolve inside the sysroot), and the BLAS/LAPACK alternatives are linked. The tree has
# no /bin/sh, so a test running under qemu that starts a shell gets the host's.
set -euo pipefail

usage() { echo "usage: $0 aarch64|armhf [--no-apt]" >&2; exit 2; }
[ $# -ge 1 ] || usage
arch=$1
shift
install_apt=1
for a in "$@"; do
  case $a in
    --no-apt) install_apt=0 ;;
    *) usage ;;
  esac
done

case $arch in
  aarch64 | arm64) arch=aarch64 debarch=arm64 triplet=aarch64-linux-gnu
    crosspkg=crossbuild-essential-arm64 ;;
  armhf | armv7) arch=armhf debarch=armhf triplet=arm-linux-gnueabihf
    crosspkg=crossbuild-essential-armhf ;;
  *) usage ;;
esac

cache=${LDSM_CROSS_CACHE:-$HOME/.cache/ldsm-cross}
sysroot=$cache/$arch
suite=${LDSM_CROSS_SUITE:-bookworm}
mirror=${LDSM_CROSS_MIRROR:-http://deb.debian.org/debian}

HOST_PACKAGES=(cmake ninja-build pkg-config ccache mmdebstrap debian-archive-keyring
  qemu-user-static "$crosspkg")
# Target packages: what scripts/install-deps.sh installs for the host build, minus the tools
# (zipcmp, zipmerge and ziptool only because libzip's CMake package checks that they exist).
# libblas3, liblapack3 and their -dev pin the reference BLAS (otherwise the resolver may pick ATLAS).
# libcivetweb-dev and libjs-three: the browser viewer (apps/viewer), built for the target too (a
# headless board is where it is used). The Python module is not cross-built (scripts/cross-test.sh).
TARGET_PACKAGES=(libc6-dev libstdc++-12-dev
  libeigen3-dev libopencv-dev libceres-dev libsuitesparse-dev libblas3 liblapack3
  libblas-dev liblapack-dev
  libspdlog-dev libfmt-dev libyaml-cpp-dev libcli11-dev
  libzip-dev zipcmp zipmerge ziptool zlib1g-dev libpng-dev libjpeg62-turbo-dev
  libv4l-dev libcamera-dev libcivetweb-dev libjs-three
  libgtest-dev libgmock-dev libbenchmark-dev)

SUDO=""
if [ "$(id -u)" -ne 0 ]; then
  if command -v sudo >/dev/null 2>&1; then SUDO="sudo"; else
    echo "prepare-sysroot.sh: needs root or sudo" >&2; exit 1; fi
fi

# ---- host packages ----------------------------------------------------------------------------
if [ "$install_apt" -eq 1 ]; then
  missing=()
  for p in "${HOST_PACKAGES[@]}"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" ||
      missing+=("$p")
  done
  if [ "${#missing[@]}" -gt 0 ]; then
    echo "prepare-sysroot.sh: installing host packages: ${missing[*]}" >&2
    export DEBIAN_FRONTEND=noninteractive
    $SUDO apt-get update -qq
    $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >&2
  fi
fi

# ---- sysroot ----------------------------------------------------------------------------------
stamp_text="ldsm sysroot v2 $suite $debarch ${TARGET_PACKAGES[*]}"
if [ -f "$sysroot/.ldsm-sysroot-stamp" ] &&
   [ "$(cat "$sysroot/.ldsm-sysroot-stamp")" = "$stamp_text" ]; then
  echo "prepare-sysroot.sh: reusing $sysroot" >&2
  echo "$sysroot"
  exit 0
fi

echo "prepare-sysroot.sh: making the $debarch sysroot in $sysroot (Debian $suite)" >&2
mkdir -p "$cache"
tmp=$sysroot.partial
$SUDO rm -rf "$tmp" "$sysroot"
mode=root
[ "$(id -u)" -eq 0 ] || mode=unshare
includes=$(IFS=,; echo "${TARGET_PACKAGES[*]}")
nice -n 15 mmdebstrap --quiet --variant=extract --mode="$mode" --arch="$debarch" \
  --skip=check/empty --include="$includes" "$suite" "$tmp" "$mirror" >&2

# Absolute symlinks (libz.so -> /lib/<triplet>/libz.so.1...) would resolve on the host: make them
# relative to their place in the sysroot.
fixed=0
while IFS= read -r -d '' link; do
  target=$(readlink "$link")
  rel=$(realpath -m -s --relative-to="$(dirname "$link")" "$tmp$target")
  ln -sfn "$rel" "$link"
  fixed=$((fixed + 1))
done < <(find "$tmp/usr" "$tmp/lib" "$tmp/etc" -type l -lname '/*' -print0)
echo "prepare-sysroot.sh: made $fixed absolute symlinks relative" >&2

# CMake packages that name libraries by absolute path (Ceres: /usr/lib/<triplet>/liblapack.so...)
# would point at the host: prefix those with the sysroot the toolchain file sets.
while IFS= read -r -d '' f; do
  if grep -q 'INTERFACE_LINK_LIBRARIES.*[";]/usr/lib/' "$f"; then
    # shellcheck disable=SC2016  # ${CMAKE_SYSROOT} is for CMake, not the shell
    sed -i '/INTERFACE_LINK_LIBRARIES/ s#\([";]\)/usr/lib/#\1${CMAKE_SYSROOT}/usr/lib/#g' "$f"
    echo "prepare-sysroot.sh: sysroot-relative library paths in ${f#"$tmp"}" >&2
  fi
done < <(find "$tmp/usr/lib" "$tmp/usr/share" -name '*.cmake' -print0)

# update-alternatives links that the libblas3/liblapack3 maintainer scripts would have made.
libdir=$tmp/usr/lib/$triplet
ln -sfn blas/libblas.so.3 "$libdir/libblas.so.3"
ln -sfn lapack/liblapack.so.3 "$libdir/liblapack.so.3"
[ -e "$libdir/blas/libblas.so" ] && ln -sfn blas/libblas.so "$libdir/libblas.so"
[ -e "$libdir/lapack/liblapack.so" ] && ln -sfn lapack/liblapack.so "$libdir/liblapack.so"

# Nothing from the target runs here except under qemu; a target /bin/sh would make qemu-run tests
# that call std::system()/popen() fail (the host kernel cannot exec it), the host's works.
rm -rf "${tmp:?}/dev" "${tmp:?}/bin/sh" "${tmp:?}/usr/bin/sh"

echo "$stamp_text" > "$tmp/.ldsm-sysroot-stamp"
mv "$tmp" "$sysroot"
echo "prepare-sysroot.sh: sysroot ready ($(du -sh "$sysroot" | cut -f1))" >&2
echo "$sysroot"
