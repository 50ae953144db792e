#!/usr/bin/env bash
# First README command: install what is missing, build in Release, run the default study.
set -euo pipefail
cd "$(dirname "$0")/.."
./scripts/install_deps.sh
./scripts/build.sh
./build/poise run studies/los_seeker_wang2011.toml
