#!/usr/bin/env bash
# First README command: install what is missing, build the poise executable in Release (only
# what it needs: the test command builds the tests, benchmarks and fuzzers), run the default study.
set -euo pipefail
cd "$(dirname "$0")/.."
./scripts/install_deps.sh
POISE_BUILD_TARGET=poise ./scripts/build.sh
./build/poise run studies/los_seeker_wang2011.toml
