#!/usr/bin/env bash
# Second README command: install what is missing, build in Release, run every test with ctest.
set -euo pipefail
cd "$(dirname "$0")/.."
./scripts/install_deps.sh --tests
./scripts/build.sh
ctest --test-dir build --output-on-failure -j"$(nproc)"
