#!/usr/bin/env bash
# Runs the glTF loader over every .gltf/.glb under the given directories and prints a table:
#   file | ok: meshes/triangles/materials/textures, warnings | refused: <message> | crash | timeout
# then the counts.  Each file is imported by tests/scene/gltf_check (one process per file, 120 s
# timeout).  Exit status: 0 when no file crashed or timed out, 1 otherwise.
#
#   scripts/corpus_gltf.sh [--tool PATH] [--timeout S] DIR...
#   e.g. scripts/corpus_gltf.sh /usr/share/assimp/models/glTF2      (Debian's assimp-testmodels)
#
# --tool: the gltf_check binary (default: build/tests/scene/gltf_check next to this script's tree);
# point it at another build (an older commit, a sanitizer build) to compare.
set -uo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
tool="$here/build/tests/scene/gltf_check"
limit=120
dirs=()
while [ $# -gt 0 ]; do
  case "$1" in
    --tool) tool="$2"; shift 2 ;;
    --timeout) limit="$2"; shift 2 ;;
    -h|--help) sed -n '2,11p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
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

n_ok=0 n_refused=0 n_crash=0 n_timeout=0
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
done < <(find "${dirs[@]}" -type f \( -iname '*.gltf' -o -iname '*.glb' \) -print0 | sort -z)

echo "files: $((n_ok + n_refused + n_crash + n_timeout)), ok $n_ok, refused $n_refused, crash $n_crash, timeout $n_timeout"
[ $n_crash -eq 0 ] && [ $n_timeout -eq 0 ]
