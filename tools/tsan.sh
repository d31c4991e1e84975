#!/usr/bin/env bash
# ThreadSanitizer run of riffle's threaded tests (docs/RELIABILITY.md, "ThreadSanitizer").
#   tools/tsan.sh [WORK_DIR]        # default build-tsan; about 15 minutes the first time on 2 cores
# Debian's libtbb is not instrumented: TSan then cannot see the task scheduler's hand-offs and reports every
# parallel_for as a race (25 reports for a five-line loop over a vector). So this script first builds oneTBB from
# Debian's own source package (onetbb, `apt-get source`; it adds a deb-src entry for bookworm if there is none) with
# clang and -fsanitize=thread into WORK_DIR/tbb, then riffle against it (clang, RIFFLE_TSAN=ON) into WORK_DIR/riffle,
# and runs the unit tests and the regression tests (the thread-count and resume determinism tests, which run every
# system on one and two threads) under TSan. Exits 1 on any report.
set -euo pipefail
cd "$(dirname "$0")/.."
work=$(mkdir -p "${1:-build-tsan}" && cd "${1:-build-tsan}" && pwd)
sudo_cmd=()
[ "$(id -u)" -eq 0 ] || sudo_cmd=(sudo)

PACKAGES_ONLY=1 EXTRA_PACKAGES="clang xz-utils" tools/setup.sh

if [ ! -f "$work/tbb/lib/cmake/TBB/TBBConfig.cmake" ]; then
  if ! grep -rqs "deb-src" /etc/apt/sources.list /etc/apt/sources.list.d/; then
    echo "tsan: adding a deb-src entry for Debian bookworm (to fetch onetbb's source package)"
    printf 'Types: deb-src\nURIs: http://deb.debian.org/debian\nSuites: bookworm\nComponents: main\nSigned-By: %s\n' \
      /usr/share/keyrings/debian-archive-keyring.gpg | "${sudo_cmd[@]}" tee /etc/apt/sources.list.d/riffle-src.sources
    "${sudo_cmd[@]}" apt-get update -qq
  fi
  mkdir -p "$work/tbb-src"
  (cd "$work/tbb-src" && apt-get source --download-only -qq onetbb && tar xf onetbb_*.orig.tar.*)
  source_dir=$(find "$work/tbb-src" -maxdepth 1 -type d -name 'oneTBB-*' | head -n 1)
  CC=clang CXX=clang++ cmake -S "$source_dir" -B "$work/tbb-build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
    -DTBB_TEST=OFF -DTBB_EXAMPLES=OFF -DTBB_STRICT=OFF -DTBB_SANITIZE=thread -DTBBMALLOC_BUILD=OFF \
    -DCMAKE_INSTALL_PREFIX="$work/tbb" > "$work/tbb-configure.log"
  cmake --build "$work/tbb-build" --parallel "$(nproc)"
  cmake --install "$work/tbb-build" > /dev/null
fi

CC=clang CXX=clang++ cmake -S . -B "$work/riffle" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DRIFFLE_TSAN=ON \
  -DTBB_DIR="$work/tbb/lib/cmake/TBB" > "$work/riffle-configure.log"
cmake --build "$work/riffle" --parallel "$(nproc)" --target riffle_unit_tests riffle_regression_tests
export TSAN_OPTIONS="halt_on_error=1 second_deadlock_stack=1 history_size=4"
export LD_LIBRARY_PATH="$work/tbb/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}"
status=0
"$work/riffle/tests/riffle_unit_tests" || status=1
# The determinism tests: every system on one and two threads, resumed and uninterrupted.
"$work/riffle/tests/riffle_regression_tests" || status=1
[ $status -eq 0 ] && echo "tsan: no data race reported" || echo "tsan: FAILED (see the reports above)"
exit $status
