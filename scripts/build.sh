#!/usr/bin/env bash
# Configures and builds Poise in Release into build/ (the executable is build/poise).
# Both README commands build in the same configuration, so that the test command compiles no
# source file the first command compiled: each library's sources in batches (CMake's unity
# build: a batch parses the headers its files share once), position-independent, warnings as
# errors with g++ 12 (CMakeLists.txt), every compilation through ccache (a clean clone on the
# same machine compiles from its cache).
# POISE_BUILD_TARGET=poise builds the executable only (the first README command), configured
# without the tests, benchmarks and Python module (so it needs none of their packages). The
# default builds everything: tests, benchmarks, fuzzers' seeds and the Python module (the test
# command). Each source file compiled alone (its own includes checked) is the sanitizer builds'
# way (scripts/sanitize.sh), and every header compiled alone is the target poise_header_check
# (.ci/run).
# POISE_BUILD_DIR: another build folder than build/.
set -euo pipefail
cd "$(dirname "$0")/.."
target="${POISE_BUILD_TARGET:-all}"
dir="${POISE_BUILD_DIR:-build}"
parts=ON
if [ "$target" = poise ]; then
  parts=OFF
fi
cmake -S . -B "$dir" -DCMAKE_BUILD_TYPE=Release -DPOISE_BUILD_TESTS=$parts -DPOISE_BUILD_BENCH=$parts \
      -DPOISE_BUILD_PYTHON=$parts -DCMAKE_UNITY_BUILD=ON "$@"
cmake --build "$dir" -j"$(nproc)" --target "$target"
