#!/usr/bin/env bash
# Second README command: install what is missing, check the format, build in Release (the same
# configuration as the first command: what it compiled is not compiled again; ccache for the
# rest), run the tests a newcomer needs with ctest: every test but the statistical batteries
# and the fuzz runs (labels `battery` and `fuzz`), which .ci/run and the nightly add.
# Warnings are errors here with g++ 12, CI's compiler (CMakeLists.txt, POISE_WERROR).
# Then the guide, built into build/docs/site (scripts/docs.sh).
# Extra arguments go to ctest (e.g. -R Interrupt, -L unit).
set -euo pipefail
cd "$(dirname "$0")/.."
./scripts/install_deps.sh --tests
# The format first (seconds): a file off .clang-format fails here, before the build; the fix is
# ./scripts/format.sh.
./scripts/check_format.sh
./scripts/build.sh
# The guide (docs/ and the reference pages generated from build/poise) with `mkdocs build
# --strict`: a broken link fails here; the `docs` tests below check the built site in Chromium
# and run every example of its pages.
./scripts/docs.sh
ctest --test-dir build --output-on-failure -j"$(nproc)" -LE '^(battery|fuzz)$' "$@"
