#!/bin/sh
# The path tracer's efficiency on the Cornell box glTF (tests/reference/cornell_box), one thread,
# 256x256, full GI, against Blender's Cycles on the same file when `blender` is installed (outside
# oracle only: scripts/oracle_cycles.py).  For each renderer: samples per pixel per CPU-second and
# CPU-s x (MSE against its own high-spp reference - that reference's own variance); lower is better.
#
# usage: scripts/efficiency_cornell.sh [--build DIR] [--out DIR] [--spp "16 64"] [--hi-spp 2048]
#                                      [--hi-threads 2] [--no-cycles]
# The high-spp references take minutes (prw: 2048 spp at ~10 spp per CPU-second; Cycles: two seeds
# of 1024); they are kept in --out and reused when present.
set -eu
here=$(cd "$(dirname "$0")/.." && pwd)
build=$here/build out=${TMPDIR:-/tmp}/prw-efficiency spps="16 64" hi=2048 hit=2 cycles=1
while [ $# -gt 0 ]; do
    case $1 in
    --build) build=$2; shift 2 ;;
    --out) out=$2; shift 2 ;;
    --spp) spps=$2; shift 2 ;;
    --hi-spp) hi=$2; shift 2 ;;
    --hi-threads) hit=$2; shift 2 ;;
    --no-cycles) cycles=0; shift ;;
    -h | --help) sed -n '2,12p' "$0"; exit 0 ;;
    *) echo "efficiency_cornell.sh: unknown argument $1" >&2; exit 2 ;;
    esac
done
prw=$build/app/prw
box=$build/tests/reference/cornell_box
for f in "$prw" "$box"; do
    [ -x "$f" ] || { echo "efficiency_cornell.sh: $f missing (build first)" >&2; exit 1; }
done
mkdir -p "$out"
"$box" "$out/cornell.gltf" >/dev/null
echo "git $(git -C "$here" rev-parse --short HEAD 2>/dev/null || echo '?'), $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //')"
if [ ! -f "$out/prw_hi.exr" ]; then
    echo "prw: high-spp reference ($hi spp, $hit threads) ..."
    "$prw" --threads "$hit" reference "$out/cornell.gltf" --size 256x256 --spp "$hi" --seed 1001 \
        --out "$out/prw_hi.exr" 2>/dev/null | grep 'samples per pixel'
fi
for n in $spps; do
    "$prw" --threads 1 reference "$out/cornell.gltf" --size 256x256 --spp "$n" --out "$out/prw_$n.exr" \
        --against "$out/prw_hi.exr" 2>/dev/null | grep -E 'per CPU-second|CPU-s x' | sed "s/^reference:/prw $n spp:/"
done
if [ "$cycles" = 0 ]; then exit 0; fi
if ! command -v blender >/dev/null 2>&1; then
    echo "cycles: SKIP (no blender; apt-get install blender)"
    exit 0
fi
oracle="blender -b --factory-startup --python $here/scripts/oracle_cycles.py --"
for s in a b; do
    if [ ! -f "$out/cycles_hi_$s.exr" ]; then
        seed=1001; [ $s = b ] && seed=1002
        echo "cycles: high-spp reference $s ($((hi / 2)) spp, $hit threads) ..."
        $oracle render "$out/cornell.gltf" "$out/cycles_hi_$s.exr" --spp $((hi / 2)) --seed $seed --threads "$hit" \
            --lambert 2>&1 | grep '^cycles:'
    fi
done
tests=""
for n in $spps; do
    $oracle render "$out/cornell.gltf" "$out/cycles_$n.exr" --spp "$n" --seed 7 --threads 1 --lambert 2>&1 |
        grep '^cycles:' | tee "$out/cycles_$n.log"
    tests="$tests $out/cycles_$n.exr"
done
# shellcheck disable=SC2086
$oracle error "$out/cycles_hi_a.exr" "$out/cycles_hi_b.exr" $tests 2>&1 | grep '^cycles-error:' | tee "$out/cycles_error.log"
for n in $spps; do
    cpu=$(sed -n 's/.*CPU-s \([0-9.]*\),.*/\1/p' "$out/cycles_$n.log")
    e=$(sed -n "s|.*cycles_$n.exr: .*MSE - variance \([-0-9.e+]*\).*|\1|p" "$out/cycles_error.log")
    awk -v n="$n" -v c="$cpu" -v e="$e" 'BEGIN { printf "cycles %s spp: %.3f samples per pixel per CPU-second, CPU-s x (MSE - variance) %.6g\n", n, n / c, c * e }'
done
