#!/usr/bin/env bash
# Installs riffle's Debian 12 packages (only those missing), configures and builds in Release into build/.
# Idempotent: a second run installs nothing and rebuilds only what changed.
#   tools/setup.sh                 # packages + Release build in build/
#   BUILD_DIR=build-asan CMAKE_ARGS="-DRIFFLE_SANITIZE=ON -DCMAKE_BUILD_TYPE=RelWithDebInfo" tools/setup.sh
#   EXTRA_PACKAGES=clang BUILD_TARGETS="riffle_unit_tests" ...   # more packages; only these targets
#   PACKAGES_ONLY=1 EXTRA_PACKAGES=clang tools/setup.sh         # only the packages
set -euo pipefail
cd "$(dirname "$0")/.."

packages=(build-essential cmake ninja-build pkg-config
          libtbb-dev libeigen3-dev libcereal-dev libspdlog-dev doctest-dev libcli11-dev libtomlplusplus-dev
          libhypre-dev python3-numpy python3-matplotlib ${EXTRA_PACKAGES:-})
missing=()
for package in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$package" 2>/dev/null | grep -q "install ok installed" || missing+=("$package")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "setup: installing ${missing[*]}"
  sudo_cmd=()
  [ "$(id -u)" -eq 0 ] || sudo_cmd=(sudo)
  "${sudo_cmd[@]}" apt-get update -qq
  DEBIAN_FRONTEND=noninteractive "${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi

[ -z "${PACKAGES_ONLY:-}" ] || exit 0  # PACKAGES_ONLY=1: install, configure and build nothing

build_dir=${BUILD_DIR:-build}
# shellcheck disable=SC2086
mkdir -p "$build_dir"
cmake -S . -B "$build_dir" -G Ninja -DCMAKE_BUILD_TYPE=Release ${CMAKE_ARGS:-} > "$build_dir/configure.log" 2>&1 ||
  { cat "$build_dir/configure.log"; exit 1; }
# shellcheck disable=SC2086
cmake --build "$build_dir" --parallel "$(nproc)" ${BUILD_TARGETS:+--target $BUILD_TARGETS}
