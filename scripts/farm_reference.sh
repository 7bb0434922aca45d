#!/usr/bin/env bash
# Renders a prw reference as a Slurm job array: task k renders sample batch k of N
# (prw reference --samples s0,s1 --acc), then prw reference-merge joins the accumulations bit-exactly
# (the same image as one process with the same seed).  Writes the sbatch file DIR/reference.sbatch
# and submits it; the merge runs as a job that depends on the array (afterok), or here with --wait.
#
#   scripts/farm_reference.sh [options] -- SCENE [prw reference options: --size, --spp, --seed, ...]
#
#   --prw PATH       the prw binary, on a path every node sees (default: build/app/prw of this checkout)
#   --out DIR        shared output directory (default prw-out/farm): part-K.acc, reference.exr/.acc, logs
#   --tasks N        array tasks (default 4; at most the sample count)
#   --cpus C         CPUs per task: Slurm's --cpus-per-task and prw's --threads (default 1)
#   --partition P    Slurm partition (default: the cluster's default)
#   --time T         time limit per task, Slurm syntax (default: the partition's)
#   --wait           wait for the array (sbatch --wait), then merge here; exit status of the merge
#   --dry-run        write the sbatch file and print the commands, submit nothing
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
prw="$here/build/app/prw"
out=prw-out/farm
tasks=4
cpus=1
partition=""
tlimit=""
wait=0
dry=0
while [ $# -gt 0 ]; do
  case "$1" in
    --prw) prw="$2"; shift 2 ;;
    --out) out="$2"; shift 2 ;;
    --tasks) tasks="$2"; shift 2 ;;
    --cpus) cpus="$2"; shift 2 ;;
    --partition) partition="$2"; shift 2 ;;
    --time) tlimit="$2"; shift 2 ;;
    --wait) wait=1; shift ;;
    --dry-run) dry=1; shift ;;
    --) shift; break ;;
    -h|--help) sed -n '2,17p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
    *) echo "farm_reference: unknown option $1 (--help)" >&2; exit 2 ;;
  esac
done
[ $# -ge 1 ] || { echo "farm_reference: give -- SCENE [prw reference options]" >&2; exit 2; }
case "$tasks$cpus" in *[!0-9]*) echo "farm_reference: --tasks and --cpus take positive integers" >&2; exit 2 ;; esac
[ "$tasks" -ge 1 ] && [ "$cpus" -ge 1 ] || { echo "farm_reference: --tasks and --cpus must be >= 1" >&2; exit 2; }
[ -x "$prw" ] || { echo "farm_reference: $prw: not an executable (--prw)" >&2; exit 2; }
spp=64
args=() # the reference options without --spp (each task gets --samples)
while [ $# -gt 0 ]; do
  case "$1" in
    --spp) spp="${2:-}"; shift 2 || shift ;;
    --samples|--acc|--out|--tile|--time-limit)
      echo "farm_reference: $1 is set per task by this script" >&2; exit 2 ;;
    *) args+=("$1"); shift ;;
  esac
done
case "$spp" in ''|*[!0-9]*) echo "farm_reference: --spp $spp: a positive integer" >&2; exit 2 ;; esac
[ "$tasks" -le "$spp" ] || { echo "farm_reference: $tasks tasks for $spp samples: at most one task per sample" >&2; exit 2; }
mkdir -p "$out"
out="$(cd "$out" && pwd)"
prw="$(cd "$(dirname "$prw")" && pwd)/$(basename "$prw")"
rm -f "$out"/part-*.acc
job="$out/reference.sbatch"
{
  echo "#!/bin/bash"
  echo "#SBATCH --job-name=prw-reference"
  echo "#SBATCH --array=0-$((tasks - 1))"
  echo "#SBATCH --ntasks=1"
  echo "#SBATCH --cpus-per-task=$cpus"
  echo "#SBATCH --output=$out/slurm-%A_%a.log"
  [ -n "$partition" ] && echo "#SBATCH --partition=$partition"
  [ -n "$tlimit" ] && echo "#SBATCH --time=$tlimit"
  echo "# written by scripts/farm_reference.sh: task k renders samples [k spp / N, (k + 1) spp / N)"
  echo "set -euo pipefail"
  echo "k=\$SLURM_ARRAY_TASK_ID"
  echo "s0=\$(( k * $spp / $tasks )); s1=\$(( (k + 1) * $spp / $tasks ))"
  printf 'exec %q --threads %s reference' "$prw" "$cpus"
  printf ' %q' "${args[@]}"
  printf ' --samples "$s0,$s1" --acc %q\n' "$out/part-\$k.acc" | sed 's/\\\$k/$k/'
} > "$job"
merge=("$prw" reference-merge)
for ((k = 0; k < tasks; k++)); do merge+=("$out/part-$k.acc"); done
merge+=(--out "$out/reference.exr" --acc "$out/reference.acc")
if [ "$dry" = 1 ]; then
  echo "wrote $job"
  echo "sbatch $job"
  printf '%q ' "${merge[@]}"; echo
  exit 0
fi
if [ "$wait" = 1 ]; then
  echo "farm_reference: submitting $tasks tasks ($spp samples) and waiting"
  sbatch --wait "$job"
  "${merge[@]}"
  echo "farm_reference: wrote $out/reference.exr"
  exit 0
fi
id=$(sbatch --parsable "$job")
id=${id%%;*}
mid=$(sbatch --parsable --dependency="afterok:$id" --job-name=prw-reference-merge --ntasks=1 \
  --output="$out/slurm-merge-%j.log" --wrap="$(printf '%q ' "${merge[@]}")")
echo "farm_reference: submitted array $id ($tasks tasks, $spp samples) and merge job ${mid%%;*}; result: $out/reference.exr"
