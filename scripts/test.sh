#!/usr/bin/env bash
# The test command: installs what is needed, builds twice (GCC with -Werror, and clang with
# ASan+UBSan and -Werror) and runs every test in both builds.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
jobs=$(nproc)
# ctest may run more tests at once than there are cores (scripts/test-under-load.sh does).
ctest_jobs=${HD_TEST_JOBS:-$jobs}
# ccache keys on paths relative to the checkout, so a fresh clone reuses earlier builds (no
# object holds an absolute path: tests/test_paths.h).
export CCACHE_BASEDIR="$PWD" CCACHE_NOHASHDIR=1
# Line tables, not full debug info: sanitizer reports and backtraces still name file:line, and
# full DWARF took a third of every compile here.
flags=(-DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O2 -g1 -DNDEBUG"
       -DCMAKE_C_FLAGS_RELWITHDEBINFO="-O2 -g1 -DNDEBUG" -DHYBRID_WERROR=ON)

echo "== build (GCC, RelWithDebInfo, -Werror) =="
cmake -S . -B build -G Ninja "${flags[@]}"
cmake --build build -j"$jobs"
echo "== tests =="
ctest --test-dir build --output-on-failure -j"$ctest_jobs"

# The sanitizer build uses clang: GCC took four times as long on the same ASan+UBSan objects
# (36 s against 9 s for one station test), and a second compiler's -Werror warnings come free.
echo "== build (clang, ASan+UBSan, -Werror) =="
cmake -S . -B build-asan -G Ninja "${flags[@]}" -DCMAKE_C_COMPILER=clang \
  -DCMAKE_CXX_COMPILER=clang++ -DHYBRID_SANITIZE=ON -DHYBRID_BENCH=OFF
cmake --build build-asan -j"$jobs"
echo "== tests under ASan+UBSan =="
export ASAN_OPTIONS="detect_leaks=1:abort_on_error=1:strict_string_checks=1:suppressions=$PWD/tests/asan.supp"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
export LSAN_OPTIONS="suppressions=$PWD/tests/lsan.supp:print_suppressions=0"
ctest --test-dir build-asan --output-on-failure -j"$ctest_jobs" -LE no_sanitizer
