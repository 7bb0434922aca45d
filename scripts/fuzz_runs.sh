#!/usr/bin/env bash
# Runs every libFuzzer target of a fuzz build for a number of executions and prints one line per
# target: executions done, seconds, new corpus entries, and crashes (artifacts are kept).
#
#   scripts/fuzz_runs.sh [--build DIR] [--runs N] [--max-time S] [--jobs J] [--only REGEX]
#
# --build: a tree configured with -DPRW_FUZZ=ON and clang (default build-asan, as scripts/test.sh
#          makes it); --runs: executions per target (default 1000000); --max-time: seconds per
#          target at most (default 1800); --jobs: targets run at the same time (default 1); --only:
#          the targets whose binary name matches the extended regular expression.
# The seed corpora are copied, not changed; new inputs and crash artifacts go to
# <build>/fuzz-runs/<target>/.  Exit status 1 when any target crashed, leaked or timed out.
set -uo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
build="$here/build-asan"
# relative --build paths are taken from the current directory
runs=1000000
max_time=1800
jobs=1
only=.
while [ $# -gt 0 ]; do
  case "$1" in
    --build) build="$(cd "$2" 2>/dev/null && pwd || echo "$2")"; shift 2 ;;
    --runs) runs="$2"; shift 2 ;;
    --max-time) max_time="$2"; shift 2 ;;
    --jobs) jobs="$2"; shift 2 ;;
    --only) only="$2"; shift 2 ;;
    -h|--help) sed -n '2,12p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
    *) echo "fuzz_runs: unknown argument $1 (--help)" >&2; exit 2 ;;
  esac
done
nfuzz=$(cd "$build" 2>/dev/null && ctest -N -L fuzz | grep -c '_libfuzzer$')
if [ "${nfuzz:-0}" -eq 0 ]; then
  echo "fuzz_runs: $build has no libFuzzer targets (configure with -DPRW_FUZZ=ON and clang)" >&2
  exit 2
fi
# "<binary> <corpus>" from the replay tests' command lines
mapfile -t cmds < <(cd "$build" && ctest -N -V -L fuzz | sed -n 's/^[0-9]*: Test command: //p' |
  awk -v re="$only" '{ n = $1; gsub(/"/, "", n); sub(/.*\//, "", n); if (n ~ re) print }')
if [ "${#cmds[@]}" -eq 0 ]; then
  echo "fuzz_runs: no libFuzzer target matches '$only'" >&2
  exit 2
fi
run_one() {
  local line="$1" bin corpus name out log
  bin=$(echo "$line" | awk '{print $1}')
  corpus=$(echo "$line" | awk '{print $NF}' | tr -d '"')
  bin=${bin//\"/}
  name=$(basename "$bin")
  out="$build/fuzz-runs/$name"
  rm -rf "$out" && mkdir -p "$out/corpus" "$out/artifacts"
  cp -r "$corpus"/. "$out/corpus/" 2>/dev/null
  log="$out/log.txt"
  (cd "$out" && "$bin" -runs="$runs" -max_total_time="$max_time" -rss_limit_mb=2048 -timeout=60 \
     -artifact_prefix="$out/artifacts/" -print_final_stats=1 corpus >"$log" 2>&1)
  local rc=$? done secs new crashes
  done=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -1)
  secs=$(grep -o 'Done [0-9]* runs in [0-9]* second' "$log" | awk '{print $5}' | tail -1)
  new=$(sed -n 's/^stat::new_units_added: *//p' "$log" | tail -1)
  crashes=$(find "$out/artifacts" -type f | wc -l)
  printf '%-28s runs %10s  %6ss  new %5s  artifacts %d  exit %d\n' "$name" "${done:-?}" "${secs:-?}" "${new:-?}" \
    "$crashes" "$rc"
  [ "$rc" -eq 0 ] && [ "$crashes" -eq 0 ]
}
export -f run_one
export build runs max_time
status=0
printf '%s\n' "${cmds[@]}" | xargs -P "$jobs" -I{} bash -c 'run_one "$@"' _ {} || status=1
exit $status
