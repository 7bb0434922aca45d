#!/usr/bin/env bash
# Runs the glTF loader over every .gltf/.glb under the given directories and prints a table:
#   file | ok: meshes/triangles/materials/textures, warnings | refused: <message> | crash | timeout
# then the counts.  Each file is imported by tests/scene/gltf_check (one process per file, 120 s
# timeout).  With --render OUTDIR every file that imports is also opened directly by
# `prw render FILE --size 160x120` (one process, same timeout) and its PNG judged by
# scripts/png_stats.py (covered and lit pixels, distinct colours: "image", or black / empty / flat / clipped).
# Exit status: 0 when no file crashed or timed out (and, with --render, every render that exited 0
# is an "image"), 1 otherwise.
#
#   scripts/corpus_gltf.sh [--tool PATH] [--prw PATH] [--timeout S] [--render OUTDIR] DIR...
#   e.g. scripts/corpus_gltf.sh --render /tmp/gltf-renders /usr/share/assimp/models/glTF2
#        (Debian's assimp-testmodels)
#
# --tool: the gltf_check binary (default: build/tests/scene/gltf_check next to this script's tree);
# --prw: the prw binary (default build/app/prw); point them at another build to compare.
set -uo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
tool="$here/build/tests/scene/gltf_check"
prw="$here/build/app/prw"
limit=120
render=""
dirs=()
while [ $# -gt 0 ]; do
  case "$1" in
    --tool) tool="$2"; shift 2 ;;
    --timeout) limit="$2"; shift 2 ;;
    --prw) prw="$2"; shift 2 ;;
    --render) render="$2"; shift 2 ;;
    -h|--help) sed -n '2,16p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
    *) dirs+=("$1"); shift ;;
  esac
done
if [ ${#dirs[@]} -eq 0 ]; then
  echo "corpus_gltf: no directory given (--help)" >&2
  exit 2
fi
if [ ! -x "$tool" ]; then
  echo "corpus_gltf: $tool is not built (cmake --build build --target gltf_check)" >&2
  exit 2
fi

if [ -n "$render" ]; then
  if [ ! -x "$prw" ]; then
    echo "corpus_gltf: $prw is not built (cmake --build build --target prw)" >&2
    exit 2
  fi
  mkdir -p "$render" || exit 2
fi

n_ok=0 n_refused=0 n_crash=0 n_timeout=0
r_image=0 r_not=0 r_refused=0 r_crash=0 r_timeout=0 k=0
while IFS= read -r -d '' f; do
  out="$(timeout "$limit" "$tool" "$f" 2>&1)"
  rc=$?
  first="$(printf '%s\n' "$out" | head -n 1)"
  case $rc in
    0) n_ok=$((n_ok + 1)); result="$first" ;;
    1) n_refused=$((n_refused + 1)); result="$first" ;;
    124) n_timeout=$((n_timeout + 1)); result="timeout (${limit} s)" ;;
    *) n_crash=$((n_crash + 1)); result="crash (exit $rc): $(printf '%s' "$out" | grep -m1 -E 'ERROR|Sanitizer|error' || true)" ;;
  esac
  printf '%s | %s\n' "$f" "$result"
  if [ $rc -eq 0 ]; then printf '%s\n' "$out" | tail -n +2 | sed 's/^/    /'; fi
  if [ -n "$render" ] && [ $rc -eq 0 ]; then
    k=$((k + 1))
    base="$render/$(printf '%03d' $k)_$(basename "$f" | tr -c 'A-Za-z0-9._\n-' '_')"
    rout="$(timeout "$limit" "$prw" render "$f" --size 160x120 --out "$base.exr" 2>&1)"
    rrc=$?
    case $rrc in
      0)
        if stats="$(python3 "$here/scripts/png_stats.py" "$base.png" 2>&1)"; then r_image=$((r_image + 1))
        else r_not=$((r_not + 1)); fi
        printf '    render: %s  (%s.png)\n' "$stats" "$base" ;;
      124) r_timeout=$((r_timeout + 1)); printf '    render: timeout (%s s)\n' "$limit" ;;
      1|2) r_refused=$((r_refused + 1))
         printf '    render refused (exit %d): %s\n' $rrc "$(printf '%s\n' "$rout" | grep -m1 -E 'error' || printf '%s' "$rout" | tail -n 1)" ;;
      *) r_crash=$((r_crash + 1)); printf '    render: crash (exit %d)\n' $rrc ;;
    esac
  fi
done < <(find "${dirs[@]}" -type f \( -iname '*.gltf' -o -iname '*.glb' \) -print0 | sort -z)

echo "files: $((n_ok + n_refused + n_crash + n_timeout)), ok $n_ok, refused $n_refused, crash $n_crash, timeout $n_timeout"
if [ -n "$render" ]; then
  echo "renders of the $n_ok that import: image $r_image, not an image $r_not, refused $r_refused, crash $r_crash, timeout $r_timeout"
  [ $n_crash -eq 0 ] && [ $n_timeout -eq 0 ] && [ $r_crash -eq 0 ] && [ $r_timeout -eq 0 ] && [ $r_not -eq 0 ]
  exit
fi
[ $n_crash -eq 0 ] && [ $n_timeout -eq 0 ]
