#!/usr/bin/env bash
# Configures and builds Poise in Release into build/ (the executable is build/poise).
# POISE_BUILD_TARGET=poise builds the executable only (the first README command); the default
# builds everything: tests, benchmarks, fuzzers and the Python module (the test command).
set -euo pipefail
cd "$(dirname "$0")/.."
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release "$@"
cmake --build build -j"$(nproc)" --target "${POISE_BUILD_TARGET:-all}"
