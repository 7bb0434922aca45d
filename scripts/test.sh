#!/usr/bin/env bash
# README command 2: set up, build and run the whole test suite.
#  1. RelWithDebInfo build, all tests (rendering tests run serially with the validation layer on).
#  2. ASan + UBSan build of the unit tests (label "unit"), with suppressions for Mesa/LLVM/the loader.
# Prints each stage's wall time.  Exit status non-zero when anything fails.
set -euo pipefail
cd "$(dirname "$0")/.."
jobs=$(nproc)
stage() { printf '\n== %s\n' "$*"; }
t0=$(date +%s)
stage "setup"
bash scripts/setup.sh

stage "build (RelWithDebInfo)"
cmake -S . -B build -DCMAKE_BUILD_TYPE=RelWithDebInfo >/dev/null
cmake --build build -j"$jobs"
t1=$(date +%s)

stage "tests"
(cd build && ctest --output-on-failure -j"$jobs")
t2=$(date +%s)

stage "sanitizer build (ASan + UBSan) and unit tests"
cmake -S . -B build-asan -DCMAKE_BUILD_TYPE=Debug -DPRW_SANITIZE=ON >/dev/null
cmake --build build-asan -j"$jobs"
export ASAN_OPTIONS="detect_leaks=1:abort_on_error=0:halt_on_error=1"
export LSAN_OPTIONS="suppressions=$PWD/tests/sanitizer/lsan.supp:print_suppressions=0"
export UBSAN_OPTIONS="suppressions=$PWD/tests/sanitizer/ubsan.supp:print_stacktrace=1:halt_on_error=1"
(cd build-asan && ctest --output-on-failure -j"$jobs" -L unit)
t3=$(date +%s)
printf '\nwall time: build %ds, tests %ds, sanitizer %ds, total %ds\n' $((t1 - t0)) $((t2 - t1)) $((t3 - t2)) $((t3 - t0))
