#!/bin/sh
# Compiler and linker launcher of the fuzz target: CMake calls
#   clang_launcher.sh <clang++> <the build's C++ compiler> <arguments...>
# and this runs <clang++> <arguments...> instead (see tests/fuzz/CMakeLists.txt), through
# ccache when POISE_FUZZ_CCACHE names it (compilations only: CMake sets it for them).
clang="$1"
shift 2
if [ -n "${POISE_FUZZ_CCACHE:-}" ]; then
  exec "$POISE_FUZZ_CCACHE" "$clang" "$@"
fi
exec "$clang" "$@"
