#!/usr/bin/env bash
# Sanitizer runs (CI runs both after the test command, .ci/run). Each has its own build folder,
# Debug (assertions on) with line tables only (-g1: every report has its functions and lines,
# and the build takes a third less than with -g), and builds only what its tests need. Both
# compile the libraries in unity batches and the tests with their shared precompiled header, as
# the README commands do, through ccache (CMakeLists.txt):
#   scripts/sanitize.sh address   AddressSanitizer + UndefinedBehaviorSanitizer (every finding
#                                 fatal) over the `unit` tests but the `battery`   build-asan/
#                                 ones (statistical batteries: the code paths of the other unit
#                                 tests, a few hundred times over; one took 460 s under ASan).
#                                 Compiled by clang++ (Debian's clang-14, which the fuzz tests
#                                 need too) at -O2: measured on 2 cores with the cache empty,
#                                 9 min 10 s against g++'s 14 min 20 s, the same 481 tests in
#                                 the same time (174 s) and no finding in either. Without clang++
#                                 it is g++ (POISE_ASAN_CXX= another compiler).
#   scripts/sanitize.sh thread    ThreadSanitizer over the `threads` tests: the threaded sample
#                                 driver, resume and MPI runs (poise itself built with TSan),
#                                 g++ at -O1                                       build-tsan/
#   scripts/sanitize.sh           both
# POISE_SANITIZE_EACH_SOURCE=1 builds every source file alone instead, the tests' without the
# precompiled header: the check that each source file's own includes suffice (a unity batch
# lends a file the includes of the files before it). It costs the TSan build twice its time,
# so the nightly makes it (.ci/nightly); poise_header_check does each header in CI.
# Extra arguments go to ctest (e.g. -R StudyRunner). Parallelism: CMAKE_BUILD_PARALLEL_LEVEL,
# else nproc. A finding in any process (a test, or a poise it runs) is written to
# build-*/sanitizer-reports/ and fails the run, whatever that process's exit status was
# checked against. Suppressions (third-party code only, each entry with its reason):
# scripts/sanitizers/.
set -euo pipefail
cd "$(dirname "$0")/.."
root="$(pwd)"
jobs="${CMAKE_BUILD_PARALLEL_LEVEL:-$(nproc)}"
which="${1:-all}"
[ $# -gt 0 ] && shift

# ThreadSanitizer sees only the synchronisation of instrumented code, and oneTBB's task
# scheduler (spawn, steal, wait) is in libtbb: with Debian's uninstrumented libtbb12 every
# hand-over of data between a task and its parent is reported as a race. So the TSan build
# links oneTBB built with -fsanitize=thread: the release Debian ships (libtbb12 2021.8.0),
# from Debian's own source tarball, built once (about 2 minutes) into the folder below.
# Embree's BVH builds then run on the same, instrumented, scheduler (one libtbb.so.12 loaded).
tbb_version=2021.8.0
tbb_sha256=7e9111b8bb59c8800bf6d0b06afe7b0891937443d2dae1ee1101c8e2ede6a7ef
# It is kept outside the checkout (~/.cache/poise/, or $XDG_CACHE_HOME/poise/), so that a clean
# clone on the same machine finds it built.
tbb_tsan() {  # prints the CMake TBB_DIR of the instrumented oneTBB
  local dir="${XDG_CACHE_HOME:-$HOME/.cache}/poise/onetbb-${tbb_version}-tsan"
  if [ ! -f "$dir/install/lib/cmake/TBB/TBBConfig.cmake" ]; then
    mkdir -p "$dir"
    if [ ! -f "$dir/onetbb.tar.xz" ]; then
      curl -sSfL -o "$dir/onetbb.tar.xz.part" \
           "http://deb.debian.org/debian/pool/main/o/onetbb/onetbb_${tbb_version}.orig.tar.xz" || return 1
      mv "$dir/onetbb.tar.xz.part" "$dir/onetbb.tar.xz"
    fi
    echo "$tbb_sha256  $dir/onetbb.tar.xz" | sha256sum -c --quiet >&2 || return 1
    rm -rf "$dir/src" && mkdir -p "$dir/src" && tar -C "$dir/src" --strip-components=1 -xf "$dir/onetbb.tar.xz" || return 1
    cmake -S "$dir/src" -B "$dir/build" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DTBB_SANITIZE=thread \
          -DTBB_TEST=OFF -DTBB_STRICT=OFF -DTBBMALLOC_BUILD=OFF -DTBB_ENABLE_IPO=OFF -DTBB_DISABLE_HWLOC_AUTOMATIC_SEARCH=ON \
          -DCMAKE_INSTALL_PREFIX="$dir/install" -DCMAKE_INSTALL_LIBDIR=lib >&2 || return 1
    cmake --build "$dir/build" -j"$jobs" >&2 || return 1
    cmake --install "$dir/build" >&2 || return 1
  fi
  echo "$dir/install/lib/cmake/TBB"
}

# (Called as `run ... || status=1`, where set -e does not apply: every step checks itself.)
run() {  # run <sanitizers> <build dir> <target> <ctest label> [ctest args]
  local sanitizers=$1 dir=$2 target=$3 label=$4
  shift 4
  local reports="$root/$dir/sanitizer-reports"
  local extra=()
  if [ "$sanitizers" = thread ]; then
    local tbb_dir
    tbb_dir="$(tbb_tsan)" || { echo "sanitize.sh: building oneTBB with TSan failed" >&2; return 1; }
    extra+=(-DTBB_DIR="$tbb_dir")
  fi
  local optimize=-O1 cxx=""
  if [ "$sanitizers" != thread ]; then
    optimize="-O2 -fno-omit-frame-pointer"
    cxx="${POISE_ASAN_CXX-$(command -v clang++-14 || command -v clang++ || true)}"
  fi
  if [ "${POISE_SANITIZE_EACH_SOURCE:-0}" = 1 ]; then
    extra+=(-DCMAKE_UNITY_BUILD=OFF -DPOISE_TEST_PCH=OFF)  # each source alone: its own includes checked
  else
    extra+=(-DCMAKE_UNITY_BUILD=ON -DPOISE_TEST_PCH=ON)
  fi
  # The compiler is fixed when a build folder is made: a folder made by another one starts afresh.
  local want="${cxx:-$(command -v c++)}"
  if [ -f "$dir/CMakeCache.txt" ] && ! grep -qx "CMAKE_CXX_COMPILER:[A-Z]*=$want" "$dir/CMakeCache.txt"; then
    rm -rf "$dir"
  fi
  if [ -n "$cxx" ]; then
    extra+=(-DCMAKE_CXX_COMPILER="$cxx")
    [[ "$cxx" == *clang++* ]] && extra+=(-DCMAKE_C_COMPILER="${cxx/clang++/clang}")  # FindHDF5's C probes
  fi
  cmake -S . -B "$dir" -DCMAKE_BUILD_TYPE=Debug -DCMAKE_CXX_FLAGS_DEBUG="-g1 $optimize" \
        -DPOISE_SANITIZE="$sanitizers" -DPOISE_WERROR=ON -DPOISE_BUILD_PYTHON=OFF -DPOISE_BUILD_BENCH=OFF \
        "${extra[@]}" || return 1
  rm -rf "$reports" && mkdir -p "$reports"
  # Findings go to files (one per process), so a poise run by a test that expects it to fail
  # cannot hide one; distinct exit codes say which sanitizer stopped a process.
  export ASAN_OPTIONS="log_path=$reports/asan:exitcode=86:detect_leaks=1:strict_string_checks=1:detect_stack_use_after_return=1:check_initialization_order=1"
  export LSAN_OPTIONS="suppressions=$root/scripts/sanitizers/lsan.supp:print_suppressions=0"
  export UBSAN_OPTIONS="log_path=$reports/ubsan:exitcode=87:print_stacktrace=1:halt_on_error=1"
  export TSAN_OPTIONS="log_path=$reports/tsan:exitcode=88:halt_on_error=0:second_deadlock_stack=1:suppressions=$root/scripts/sanitizers/tsan.supp:print_suppressions=0"
  cmake --build "$dir" -j"$jobs" --target "$target" || return 1
  local status=0
  ctest --test-dir "$dir" -L "$label" --no-tests=error --output-on-failure -j"$jobs" "$@" || status=$?
  if compgen -G "$reports/*" >/dev/null; then
    echo "sanitize.sh: $sanitizers: findings ($reports):"
    for f in "$reports"/*; do echo "== $f"; cat "$f"; done
    status=1
  fi
  if [ "$status" -ne 0 ]; then
    echo "sanitize.sh: $sanitizers over the '$label' tests FAILED"
  else
    echo "sanitize.sh: $sanitizers over the '$label' tests: no findings"
  fi
  return "$status"
}

status=0
case "$which" in
  address|asan) run address,undefined build-asan poise_unit_tests_but_batteries unit -LE battery "$@" || status=1 ;;
  thread|tsan) run thread build-tsan poise_thread_tests threads "$@" || status=1 ;;
  all)
    (run address,undefined build-asan poise_unit_tests_but_batteries unit -LE battery "$@") || status=1
    (run thread build-tsan poise_thread_tests threads "$@") || status=1 ;;
  *) echo "usage: scripts/sanitize.sh [address|thread|all] [ctest args]" >&2; exit 2 ;;
esac
exit "$status"
