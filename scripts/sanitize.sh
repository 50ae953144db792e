#!/usr/bin/env bash
# Sanitizer runs (CI runs both after the test command, .ci/run). Each has its own build folder,
# Debug (assertions on) at -O1, and builds only what its tests need:
#   scripts/sanitize.sh address   AddressSanitizer + UndefinedBehaviorSanitizer (every finding
#                                 fatal) over the `unit` tests                     build-asan/
#   scripts/sanitize.sh thread    ThreadSanitizer over the `threads` tests: the threaded sample
#                                 driver, resume and MPI runs (poise itself built with TSan)
#                                                                                  build-tsan/
#   scripts/sanitize.sh           both
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

run() {  # run <sanitizers> <build dir> <target> <ctest label> [ctest args]
  local sanitizers=$1 dir=$2 target=$3 label=$4
  shift 4
  local reports="$root/$dir/sanitizer-reports"
  cmake -S . -B "$dir" -DCMAKE_BUILD_TYPE=Debug -DCMAKE_CXX_FLAGS_DEBUG="-g -O1" \
        -DPOISE_SANITIZE="$sanitizers" -DPOISE_WERROR=ON -DPOISE_BUILD_PYTHON=OFF -DPOISE_BUILD_BENCH=OFF
  rm -rf "$reports" && mkdir -p "$reports"
  # Findings go to files (one per process), so a poise run by a test that expects it to fail
  # cannot hide one; distinct exit codes say which sanitizer stopped a process.
  export ASAN_OPTIONS="log_path=$reports/asan:exitcode=86:detect_leaks=1:strict_string_checks=1:detect_stack_use_after_return=1:check_initialization_order=1:strict_init_order=1"
  export LSAN_OPTIONS="suppressions=$root/scripts/sanitizers/lsan.supp:print_suppressions=0"
  export UBSAN_OPTIONS="log_path=$reports/ubsan:exitcode=87:print_stacktrace=1:halt_on_error=1"
  export TSAN_OPTIONS="log_path=$reports/tsan:exitcode=88:halt_on_error=0:second_deadlock_stack=1:suppressions=$root/scripts/sanitizers/tsan.supp:print_suppressions=0"
  cmake --build "$dir" -j"$jobs" --target "$target"
  local status=0
  ctest --test-dir "$dir" -L "$label" --output-on-failure -j"$jobs" "$@" || status=$?
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
  address|asan) run address,undefined build-asan poise_unit_tests unit "$@" || status=1 ;;
  thread|tsan) run thread build-tsan poise_thread_tests threads "$@" || status=1 ;;
  all)
    (run address,undefined build-asan poise_unit_tests unit "$@") || status=1
    (run thread build-tsan poise_thread_tests threads "$@") || status=1 ;;
  *) echo "usage: scripts/sanitize.sh [address|thread|all] [ctest args]" >&2; exit 2 ;;
esac
exit "$status"
