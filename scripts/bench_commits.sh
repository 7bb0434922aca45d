#!/usr/bin/env bash
# Frame time of two builds of prw on the same benchmark, alternating runs (the machine's drift and
# other load hit both alike): render core must-show 8.
#   scripts/bench_commits.sh OLD_PRW NEW_PRW [RUNS] [-- bench options]
# Runs `prw --threads 2 bench --path demo --size 1280x720 --frames-limit 30 --reference-every 1000
# --ref-spp 2 <options>` RUNS times (default 3) with each binary, old first, alternating, and prints
# each run's median frame time (frames.csv, frame_ms) and new/old of the medians of the run medians.
# (References are not what is timed: one reference frame at 2 spp keeps their set-up short; the bench
# renders references before it times anything.)
set -euo pipefail
old=$1 new=$2 runs=${3:-3}
shift 3 || shift $#
[ "${1:-}" = "--" ] && shift
work=$(mktemp -d /tmp/prw-benchcmp.XXXXXX)
median_of_csv() { # median of column frame_ms (4th) of frames.csv rows
  grep -E '^[0-9]+,' "$1" | cut -d, -f4 | sort -g | awk '{a[NR]=$1} END {print (NR%2) ? a[(NR+1)/2] : (a[NR/2]+a[NR/2+1])/2}'
}
declare -a mo mn
for i in $(seq 1 "$runs"); do
  for side in old new; do
    bin=$old; [ $side = new ] && bin=$new
    out=$work/$side-$i
    "$bin" --threads 2 bench --path demo --size 1280x720 --frames-limit 30 --reference-every 1000 --ref-spp 2 \
      --out "$out" "$@" >"$out.log" 2>&1 || { echo "bench_commits: $side run $i failed (see $out.log)"; exit 1; }
    m=$(median_of_csv "$out/frames.csv")
    echo "run $i $side: median frame $m ms"
    if [ $side = old ]; then mo+=("$m"); else mn+=("$m"); fi
  done
done
med() { printf '%s\n' "$@" | sort -g | awk '{a[NR]=$1} END {print (NR%2) ? a[(NR+1)/2] : (a[NR/2]+a[NR/2+1])/2}'; }
o=$(med "${mo[@]}") n=$(med "${mn[@]}")
echo "old median of run medians $o ms, new $n ms, new/old $(awk -v a="$n" -v b="$o" 'BEGIN {printf "%.4f", a / b}')"
echo "results in $work"
