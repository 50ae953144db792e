#!/usr/bin/env bash
# Formats src/ and python/*.{h,cc} in place by .clang-format (clang-format 14, Debian 12's
# clang-format-14): what scripts/check_format.sh checks.
set -euo pipefail
cd "$(dirname "$0")/.."
CLANG_FORMAT="${CLANG_FORMAT:-clang-format-14}"
mapfile -t files < <(./scripts/format_files.sh)
"$CLANG_FORMAT" -i "${files[@]}"
echo "format: ${#files[@]} files formatted"
