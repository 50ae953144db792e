#!/usr/bin/env bash
# Configures and builds Poise in Release into build/ (the executable is build/poise).
# POISE_BUILD_TARGET=poise builds the executable only (the first README command), configured
# without the tests, benchmarks and Python module (so it needs none of their packages), and
# compiles the sources of each library in batches (CMake's unity build: a batch parses the
# headers its files share once; README, Two commands, gives the measured times). The default
# builds everything, each source file compiled alone so that its own includes and warnings are
# checked: tests, benchmarks, fuzzers and the Python module (the test command).
# POISE_BUILD_DIR: another build folder than build/ (CI builds the first command's way there).
set -euo pipefail
cd "$(dirname "$0")/.."
target="${POISE_BUILD_TARGET:-all}"
dir="${POISE_BUILD_DIR:-build}"
parts=ON
unity=OFF
if [ "$target" = poise ]; then
  parts=OFF
  unity=ON
fi
cmake -S . -B "$dir" -DCMAKE_BUILD_TYPE=Release -DPOISE_BUILD_TESTS=$parts -DPOISE_BUILD_BENCH=$parts \
      -DPOISE_BUILD_PYTHON=$parts -DCMAKE_UNITY_BUILD=$unity "$@"
cmake --build "$dir" -j"$(nproc)" --target "$target"
