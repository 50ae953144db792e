#!/usr/bin/env bash
# The C++ files that follow .clang-format (sourced by check_format.sh and format.sh): src/ and
# python/*.{h,cc}, one per line, relative to the repository root.
find src -name '*.h' -o -name '*.cc' | sort
find python -maxdepth 1 \( -name '*.h' -o -name '*.cc' \) | sort
