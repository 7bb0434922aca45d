#!/usr/bin/env bash
# Renders the same scenes with an older commit and with this tree (or a newer commit) and compares the
# HDR EXRs bit for bit (pixels only: attributes such as the git hash differ by design).  Issue "Render
# core", must-show 1.
#   scripts/bitident.sh [OLD_COMMIT] [--new COMMIT] [--size WxH] [--keep]
# OLD_COMMIT defaults to 46f70f0 (the last commit before the render-graph rewrite); --new defaults to
# this tree (its build/).  Commits are built in temporary worktrees (RelWithDebInfo, target prw only).
# The render core itself is pixel-neutral: compare 46f70f0 with bb8655e (the render core complete);
# later commits change pixels on purpose (float32 radiance by default, the light-leak fix of the shadow
# lookup).
# The scene set (scripts/bitident/scenes.sh): the demo mono, --stereo, --hmd dk2, supersampled, 1x MSAA,
# with stereo reprojection (4x and 1x MSAA), the multiview backend, the local tone map, and the render
# tests' scenes as manifests (a point light over a Lambert plane, shadowed point/spot/directional
# lights, a scene 1e5 m from the origin, the procedural car shell and box, IGES files).
# Exit 0 only when every file is identical.
set -euo pipefail
cd "$(dirname "$0")/.."
root=$PWD
old=46f70f0
new=
size=320x180
keep=0
while [ $# -gt 0 ]; do
  case "$1" in
    --size) size=$2; shift 2 ;;
    --new) new=$2; shift 2 ;;
    --keep) keep=1; shift ;;
    -h|--help) sed -n 2,12p "$0"; exit 0 ;;
    *) old=$1; shift ;;
  esac
done
work=$(mktemp -d /tmp/prw-bitident.XXXXXX)
cleanup() {
  git -C "$root" worktree remove --force "$work/old" >/dev/null 2>&1 || true
  git -C "$root" worktree remove --force "$work/new" >/dev/null 2>&1 || true
  [ $keep = 1 ] || rm -rf "$work"
}
trap cleanup EXIT
newname=${new:-$(git rev-parse --short HEAD)$(git diff --quiet || echo '-dirty')}
echo "bitident: old $old, new $newname, size $size, work $work"
cmake -S . -B build -DCMAKE_BUILD_TYPE=RelWithDebInfo >/dev/null
cmake --build build -j"$(nproc)" --target prw exr_bitdiff >/dev/null
newbin=$root/build/app/prw
if [ -n "$new" ]; then
  git worktree add --detach "$work/new" "$new" >/dev/null 2>&1
  cmake -S "$work/new" -B "$work/new/build" -DCMAKE_BUILD_TYPE=RelWithDebInfo >/dev/null
  echo "bitident: building $new ..."
  cmake --build "$work/new/build" -j"$(nproc)" --target prw >/dev/null
  newbin=$work/new/build/app/prw
fi
git worktree add --detach "$work/old" "$old" >/dev/null 2>&1
cmake -S "$work/old" -B "$work/old/build" -DCMAKE_BUILD_TYPE=RelWithDebInfo >/dev/null
echo "bitident: building $old ..."
cmake --build "$work/old/build" -j"$(nproc)" --target prw >/dev/null
source scripts/bitident/scenes.sh
mkdir -p "$work/scenes" "$work/out-old" "$work/out-new"
bitident_write_scenes "$work/scenes" "$root/assets"
export PRW_CACHE_DIR=$work/cache LP_NUM_THREADS=${LP_NUM_THREADS:-2}
fails=0
pairs=()
for run in "${BITIDENT_RUNS[@]}"; do
  name=${run%%|*}
  args=${run#*|}
  args=${args//@/$work/scenes/}
  for side in old new; do
    bin=$newbin
    [ $side = old ] && bin=$work/old/build/app/prw
    # shellcheck disable=SC2086
    if ! "$bin" render $args --size "$size" --out "$work/out-$side/$name.exr" >"$work/out-$side/$name.log" 2>&1; then
      echo "bitident: $side failed on '$name' (see $work/out-$side/$name.log)"; fails=$((fails + 1))
    fi
  done
  for f in "$work/out-old/$name"*.exr; do
    [ -e "$f" ] || continue
    pairs+=("$f" "$work/out-new/$(basename "$f")")
  done
done
set +e
"$root/build/tests/tools/exr_bitdiff" "${pairs[@]}" | sed "s|$work/||g"
rc=$?
set -e
n=$((${#pairs[@]} / 2))
if [ $rc -eq 0 ] && [ $fails -eq 0 ]; then echo "bitident: all $n EXRs bit-identical"; exit 0; fi
echo "bitident: DIFFERENCES ($fails failed runs; see above)"; exit 1
