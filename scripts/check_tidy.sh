#!/usr/bin/env bash
# Runs clang-tidy 14 (Debian 12's clang-tidy-14) with .clang-tidy's checks over src/ and fails on
# any finding, each printed once (a header's findings come from every file that includes it).
# Uses build/compile_commands.json (configured here if missing; POISE_TIDY_BUILD=dir for another
# build folder). Arguments: regexes of the files to check instead of all of src/, e.g.
#   ./scripts/check_tidy.sh src/optimize/          ./scripts/check_tidy.sh 'sample_driver\.cc$'
# All of src/ takes about 46 CPU-minutes (README, Contributing): not run by scripts/test.sh.
set -euo pipefail
cd "$(dirname "$0")/.."
RUN_CLANG_TIDY="${RUN_CLANG_TIDY:-run-clang-tidy-14}"
CLANG_TIDY="${CLANG_TIDY:-clang-tidy-14}"
BUILD="${POISE_TIDY_BUILD:-build}"
for tool in "$RUN_CLANG_TIDY" "$CLANG_TIDY"; do
  if ! command -v "$tool" > /dev/null; then
    echo "check_tidy: $tool not found (Debian 12: apt-get install clang-tidy-14, or ./scripts/install_deps.sh --tests)" >&2
    exit 2
  fi
done
if [ ! -f "$BUILD/compile_commands.json" ]; then  # configuring is enough: generated headers exist then
  cmake -S . -B "$BUILD" -DCMAKE_BUILD_TYPE=Release -DCMAKE_EXPORT_COMPILE_COMMANDS=ON > /dev/null
fi
if [ $# -eq 0 ]; then set -- "^$PWD/src/"; fi
log=$(mktemp)
trap 'rm -f "$log"' EXIT
status=0
"$RUN_CLANG_TIDY" -quiet -j "${POISE_TIDY_JOBS:-$(nproc)}" -clang-tidy-binary "$(command -v "$CLANG_TIDY")" \
  -p "$BUILD" "$@" > "$log" 2>&1 || status=$?
findings=$(sed 's/\x1b\[[0-9;]*m//g' "$log" | grep -E '^[^ ]+:[0-9]+:[0-9]+: (warning|error): ' | sort -u || true)
if [ -n "$findings" ]; then
  echo "$findings"
  echo "check_tidy: $(wc -l <<< "$findings") findings (the notes and fixes: $RUN_CLANG_TIDY -p $BUILD FILE)" >&2
  exit 1
fi
if [ "$status" -ne 0 ]; then
  sed 's/\x1b\[[0-9;]*m//g' "$log" | tail -20 >&2
  echo "check_tidy: $RUN_CLANG_TIDY failed (exit $status)" >&2
  exit 2
fi
echo "check_tidy: no findings"
