#!/usr/bin/env bash
# README command 2: set up, build and run the whole test suite.
#  1. RelWithDebInfo build, all tests (rendering tests one at a time (RESOURCE_LOCK) with the validation layer on).
#  2. clang build with ASan + UBSan (Debug, -O1) and the libFuzzer targets (PRW_FUZZ=ON), one build
#     for both: every test (unit, cli and render; heavy cases in light mode, tests/testlib/prw_test.h)
#     with suppressions for Mesa/LLVM/the loader, and every libFuzzer target replaying its seed corpus
#     once (label "fuzz"; tests/CMakeLists.txt refuses to configure when a libFuzzer target has no
#     corpus replay).
#  3. Release build (gcc -O3) of prw and every library it links, no tests: warnings that only the
#     optimiser finds (-Werror=maybe-uninitialized) cannot land.
#  2 and 3 build in the background at nice 19 during the tests before them (idle cycles only).
# Prints each stage's wall time.  Exit status non-zero when anything fails.
set -euo pipefail
cd "$(dirname "$0")/.."
jobs=$(nproc)
stage() { printf '\n== %s\n' "$*"; }
# ctest starts the tests it knows to be long first, from the times of earlier runs; a fresh clone has
# none, so it gets measured ones (regenerate: cp build/Testing/Temporary/CTestCostData.txt
# tests/ctest_costs.txt, and the same from build-asan to tests/ctest_costs_asan.txt, after a full run).
seed_costs() {
  mkdir -p "$1/Testing/Temporary"
  [ -f "$1/Testing/Temporary/CTestCostData.txt" ] || cp "$2" "$1/Testing/Temporary/CTestCostData.txt"
}
t0=$(date +%s)
stage "setup"
bash scripts/setup.sh

stage "build (RelWithDebInfo)"
cmake -S . -B build -DCMAKE_BUILD_TYPE=RelWithDebInfo >/dev/null
cmake --build build -j"$jobs"
t1=$(date +%s)

# The sanitizer and Release builds start in the background at nice 19 while the tests of the stage
# before them run: they take only the cycles those tests leave idle (a rendering test compiling its
# pipelines keeps one core busy, and the tails are serial), and are finished in the foreground.
trap 'kill $(jobs -p) 2>/dev/null || true' EXIT
bg_build() { # dir [args]: nice 19, output to dir.log, exit status to dir.rc
  local dir=$1
  shift
  rm -f "$dir.rc" "$dir.pgid"
  # in a process group of its own (setsid; its id in dir.pgid), so that bg_finish can stop it whole
  (setsid sh -c 'echo $$ >"$0.pgid"; exec nice -n 19 cmake --build "$0" "$@"' "$dir" -j"$jobs" "$@" \
    >"$dir.log" 2>&1; echo $? >"$dir.rc") &
  bg_pid=$!
}
stop_group() { # dir: SIGTERM to its background build's process group (make deletes half-built targets)
  local g
  g=$(cat "$1.pgid" 2>/dev/null || true)
  if [ -n "$g" ]; then kill -TERM -- "-$g" 2>/dev/null || true; fi
}
bg_finish() { # dir: a failed background build shows its log; one still running is stopped, since at
  # nice 19 it starves on a busy machine (2 CPU hogs: the sanitizer build made 5 % in 25 min), and
  # the caller's foreground build finishes the rest at normal priority
  if [ ! -f "$1.rc" ]; then
    stop_group "$1"
    wait "$bg_pid" 2>/dev/null || true
    return 0
  fi
  wait "$bg_pid" 2>/dev/null || true
  if [ "$(cat "$1.rc" 2>/dev/null)" != 0 ]; then
    cat "$1.log" >&2
    echo "background build of $1 failed" >&2
    exit 1
  fi
}

# -gline-tables-only: enough for the sanitizers' file:line reports, and a faster build than -g.
cmake -S . -B build-asan -DCMAKE_BUILD_TYPE=Debug -DPRW_SANITIZE=ON -DPRW_FUZZ=ON \
  -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ \
  -DCMAKE_C_FLAGS_DEBUG=-gline-tables-only -DCMAKE_CXX_FLAGS_DEBUG=-gline-tables-only >/dev/null
nfuzz=$(cd build-asan && ctest -N -L fuzz | grep -c '_libfuzzer$' || true)
if [ "$nfuzz" -eq 0 ]; then
  echo "no fuzz targets registered (ctest -L fuzz)" >&2
  exit 1
fi
bg_build build-asan

stage "tests (the sanitizer build runs in the background at nice 19)"
seed_costs build tests/ctest_costs.txt
(cd build && ctest --output-on-failure -j"$jobs")
t2=$(date +%s)

stage "sanitizer + fuzz build (clang, ASan + UBSan, libFuzzer), rest of it, and all tests"
bg_finish build-asan
cmake --build build-asan -j"$jobs"
cmake -S . -B build-release -DCMAKE_BUILD_TYPE=Release >/dev/null
bg_build build-release --target prw
export ASAN_OPTIONS="detect_leaks=1:abort_on_error=0:halt_on_error=1"
export LSAN_OPTIONS="suppressions=$PWD/tests/sanitizer/lsan.supp:print_suppressions=0"
export UBSAN_OPTIONS="suppressions=$PWD/tests/sanitizer/ubsan.supp:print_stacktrace=1:halt_on_error=1"
seed_costs build-asan tests/ctest_costs_asan.txt
(cd build-asan && ctest --output-on-failure -j"$jobs")
t3=$(date +%s)

stage "Release build (gcc -O3): prw and its libraries, rest of it"
bg_finish build-release
cmake --build build-release -j"$jobs" --target prw
t5=$(date +%s)
printf '\nwall time: build %ds, tests %ds, sanitizer + fuzz %ds, release build %ds, total %ds\n' $((t1 - t0)) \
  $((t2 - t1)) $((t3 - t2)) $((t5 - t3)) $((t5 - t0))
