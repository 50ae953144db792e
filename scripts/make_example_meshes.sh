#!/usr/bin/env bash
# Makes the meshes of the worked example of a designer's own parts (examples/user_parts):
# builds poise_make_example_meshes (geometry/generators.h parts, each checked as
# `poise mass-properties` checks a CAD export) and writes them, in mm, to
# examples/user_parts/meshes/{rotor,seeker}/ (or to the folder given).
#   scripts/make_example_meshes.sh [OUT_DIR]
set -euo pipefail
cd "$(dirname "$0")/.."
out="${1:-examples/user_parts/meshes}"
if [ ! -f build/CMakeCache.txt ]; then
  cmake -S . -B build -DCMAKE_BUILD_TYPE=Release
fi
cmake --build build -j"$(nproc)" --target poise_make_example_meshes
build/poise_make_example_meshes "$out"
