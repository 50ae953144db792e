#!/usr/bin/env bash
# The whole test suite, several times in a row, on a machine kept busy: a test that races the
# machine (a signal after N lines, a sleep, a timeout, a file size) fails here. Issue 50 item 1.
#   scripts/stress_tests.sh                 3 rounds of every test (ctest -j4), a busy loop on
#                                           each core beside them
#   scripts/stress_tests.sh --rounds 1 -L unit   fewer rounds; further arguments go to ctest
# Builds nothing: it runs the tests of build/ (POISE_BUILD_DIR for another folder); build them
# first (scripts/build.sh). ctest's per-test timeouts are hang guards of many minutes; each
# round's log is kept in build/stress/round_N.log, and the script exits 1 if any test failed in
# any round. Run nightly with bench/nightly (.ci/nightly).
set -euo pipefail
cd "$(dirname "$0")/.."
dir="${POISE_BUILD_DIR:-build}"
rounds=3
if [ "${1:-}" = "--rounds" ]; then
  rounds="${2:?--rounds N}"
  shift 2
fi
[ -f "$dir/CTestTestfile.cmake" ] || { echo "stress_tests.sh: no tests in $dir (run scripts/build.sh first)" >&2; exit 2; }
cores="$(nproc)"
mkdir -p "$dir/stress"

busy=()
stop_busy() {
  for p in "${busy[@]}"; do kill "$p" 2>/dev/null || true; done
  wait 2>/dev/null || true
}
trap stop_busy EXIT
for _ in $(seq "$cores"); do
  (while :; do :; done) &
  busy+=($!)
done
echo "stress_tests.sh: $rounds rounds of ctest -j4 on $cores cores, a busy loop on each core (pids ${busy[*]})"

failed_rounds=0
for r in $(seq "$rounds"); do
  log="$dir/stress/round_$r.log"
  start=$(date +%s)
  status=0
  ctest --test-dir "$dir" -j4 --output-on-failure "$@" > "$log" 2>&1 || status=$?
  summary="$(grep -E "tests passed|tests failed" "$log" | tail -n 1 || true)"
  echo "round $r: exit $status, $(( $(date +%s) - start )) s: ${summary:-no summary (see $log)}"
  if [ "$status" -ne 0 ]; then
    failed_rounds=$((failed_rounds + 1))
    sed -n '/The following tests FAILED/,$p' "$log"
  fi
done
stop_busy
trap - EXIT
if [ "$failed_rounds" -ne 0 ]; then
  echo "stress_tests.sh: FAILED in $failed_rounds of $rounds rounds (logs: $dir/stress/)"
  exit 1
fi
echo "stress_tests.sh: $rounds of $rounds rounds passed under load"
