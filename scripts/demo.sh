#!/usr/bin/env bash
# README command 1: set up, build, and run the main job on the built-in demo scene.
# With a display: a window.  Without: a headless render to prw-out/demo.exr + prw-out/demo.png.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
cmake -S . -B build -DCMAKE_BUILD_TYPE=RelWithDebInfo >/dev/null
cmake --build build -j"$(nproc)"
exec ./build/app/prw "$@"
