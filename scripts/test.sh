#!/usr/bin/env bash
# The test command: installs what is needed, builds twice (plain with -Werror, and ASan+UBSan)
# and runs every test in both builds.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
jobs=$(nproc)
# ctest may run more tests at once than there are cores (scripts/test-under-load.sh does).
ctest_jobs=${HD_TEST_JOBS:-$jobs}
# ccache keys on paths relative to the checkout, so a fresh clone reuses earlier builds.
export CCACHE_BASEDIR="$PWD" CCACHE_NOHASHDIR=1

echo "== build (RelWithDebInfo, -Werror) =="
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DHYBRID_WERROR=ON
cmake --build build -j"$jobs"
echo "== tests =="
ctest --test-dir build --output-on-failure -j"$ctest_jobs"

echo "== build (ASan+UBSan) =="
cmake -S . -B build-asan -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DHYBRID_WERROR=ON \
  -DHYBRID_SANITIZE=ON -DHYBRID_BENCH=OFF
cmake --build build-asan -j"$jobs"
echo "== tests under ASan+UBSan =="
export ASAN_OPTIONS="detect_leaks=1:abort_on_error=1:strict_string_checks=1"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
export LSAN_OPTIONS="suppressions=$PWD/tests/lsan.supp:print_suppressions=0"
ctest --test-dir build-asan --output-on-failure -j"$ctest_jobs" -LE no_sanitizer
