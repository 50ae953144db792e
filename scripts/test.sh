#!/usr/bin/env bash
# Second README command: install what is missing, build in Release, run every test with ctest.
# Warnings are errors here (POISE_WERROR, as in CI); a plain build only shows them.
set -euo pipefail
cd "$(dirname "$0")/.."
./scripts/install_deps.sh --tests
./scripts/build.sh -DPOISE_WERROR=ON
ctest --test-dir build --output-on-failure -j"$(nproc)"
