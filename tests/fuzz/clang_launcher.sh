#!/bin/sh
# Compiler and linker launcher of the fuzz target: CMake calls
#   clang_launcher.sh <clang++> <the build's C++ compiler> <arguments...>
# and this runs <clang++> <arguments...> instead (see tests/fuzz/CMakeLists.txt).
clang="$1"
shift 2
exec "$clang" "$@"
