#!/usr/bin/env bash
# Checks that src/ and python/*.{h,cc} follow .clang-format (clang-format 14, Debian 12's
# clang-format-14; another version formats a few constructs differently). Prints each file that
# does not and exits 1; scripts/format.sh fixes them. A few seconds; scripts/test.sh runs it first.
set -euo pipefail
cd "$(dirname "$0")/.."
CLANG_FORMAT="${CLANG_FORMAT:-clang-format-14}"
if ! command -v "$CLANG_FORMAT" > /dev/null; then
  echo "check_format: $CLANG_FORMAT not found (Debian 12: apt-get install clang-format-14, or ./scripts/install_deps.sh --tests)" >&2
  exit 2
fi
mapfile -t files < <(./scripts/format_files.sh)
# --dry-run -Werror: one error per file that would change (--ferror-limit=1), every file checked.
status=0
out=$("$CLANG_FORMAT" --dry-run -Werror --ferror-limit=1 "${files[@]}" 2>&1) || status=$?
bad=$(sed -n 's/^\(.*\):[0-9]*:[0-9]*: error: code should be clang-formatted.*/\1/p' <<< "$out" | sort -u)
if [ "$status" -ne 0 ] && [ -z "$bad" ]; then  # not a format finding: a bad .clang-format, a missing file
  echo "$out" >&2
  echo "check_format: $CLANG_FORMAT failed (exit $status)" >&2
  exit 2
fi
if [ -n "$bad" ]; then
  echo "check_format: these files do not follow .clang-format:" >&2
  echo "$bad" | sed 's/^/  /' >&2
  echo "check_format: run ./scripts/format.sh to format them (clang-format-14 -i), then commit" >&2
  exit 1
fi
echo "check_format: ${#files[@]} files follow .clang-format"
