#!/usr/bin/env bash
# Frame time of two builds of prw on the demo still, alternating runs: `prw --threads 2 render demo
# --size WxH --frames N` (the median of N timed frames after one warm-up, as `frame time` prints it),
# RUNS times per binary, old first.  Prints every run and new/old of the medians of the run medians.
#   scripts/time_commits.sh OLD_PRW NEW_PRW [RUNS] [-- render options for both]
set -euo pipefail
old=$1 new=$2 runs=${3:-3}
shift 3 || shift $#
[ "${1:-}" = "--" ] && shift
work=$(mktemp -d /tmp/prw-timecmp.XXXXXX)
declare -a mo mn
for i in $(seq 1 "$runs"); do
  for side in old new; do
    bin=$old; [ $side = new ] && bin=$new
    m=$("$bin" --threads 2 render demo --size 1280x720 --frames 30 --out "$work/$side.exr" "$@" 2>&1 |
        sed -n 's/^frame time \([0-9.]*\) ms.*/\1/p')
    [ -n "$m" ] || { echo "time_commits: $side run $i failed"; exit 1; }
    echo "run $i $side: median frame $m ms"
    if [ $side = old ]; then mo+=("$m"); else mn+=("$m"); fi
  done
done
med() { printf '%s\n' "$@" | sort -g | awk '{a[NR]=$1} END {print (NR%2) ? a[(NR+1)/2] : (a[NR/2]+a[NR/2+1])/2}'; }
o=$(med "${mo[@]}") n=$(med "${mn[@]}")
echo "old median of run medians $o ms, new $n ms, new/old $(awk -v a="$n" -v b="$o" 'BEGIN {printf "%.4f", a / b}')"
