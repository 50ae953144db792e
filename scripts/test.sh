#!/usr/bin/env bash
# Second README command: install what is missing, check the format, build in Release, run every
# test with ctest.
# Warnings are errors here (POISE_WERROR, as in CI); a plain build only shows them.
set -euo pipefail
cd "$(dirname "$0")/.."
./scripts/install_deps.sh --tests
# The format first (seconds): a file off .clang-format fails here, before the build; the fix is
# ./scripts/format.sh.
./scripts/check_format.sh
./scripts/build.sh -DPOISE_WERROR=ON
ctest --test-dir build --output-on-failure -j"$(nproc)"
