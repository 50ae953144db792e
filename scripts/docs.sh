#!/usr/bin/env bash
# Builds the guide (docs/ and the pages generated from build/poise) into build/docs/site with
# `mkdocs build --strict`: a broken link, a missing anchor or a page outside the navigation fails
# it. The test command (scripts/test.sh) runs it; open build/docs/site/index.html in a browser.
# Needs a full build (build/poise and the Python module: ./scripts/build.sh) and Debian's mkdocs
# and chromium (scripts/install_deps.sh --tests).
#   scripts/docs.sh [--build DIR]
set -euo pipefail
cd "$(dirname "$0")/.."
exec /usr/bin/python3 scripts/docs/build_guide.py "$@"
