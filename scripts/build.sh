#!/usr/bin/env bash
# Configures and builds Poise in Release into build/ (the executable is build/poise).
# POISE_BUILD_TARGET=poise builds the executable only (the first README command), configured
# without the tests, benchmarks and Python module (so it needs none of their packages); the
# default builds everything: tests, benchmarks, fuzzers and the Python module (the test command).
set -euo pipefail
cd "$(dirname "$0")/.."
target="${POISE_BUILD_TARGET:-all}"
parts=ON
[ "$target" = poise ] && parts=OFF
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DPOISE_BUILD_TESTS=$parts -DPOISE_BUILD_BENCH=$parts \
      -DPOISE_BUILD_PYTHON=$parts "$@"
cmake --build build -j"$(nproc)" --target "$target"
