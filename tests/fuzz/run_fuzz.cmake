# ctest driver of one fuzz_<input> test: writes the seed corpus of the input kind (its
# selector bytes, see fuzz_inputs.cc) to a fresh folder of the build tree (the repository's
# files are never modified), then fuzzes for SECONDS seconds.
# Variables: FUZZER, NAME, WORK_DIR, SELECTORS, DICT, SECONDS, MAX_LEN. A finding (crash,
# sanitizer report, timeout of one input, out-of-memory, uncaught exception) fails the test
# and leaves the input that caused it in WORK_DIR (crash-*, timeout-*, oom-*); reproduce
# with `FUZZER <that file>`.
foreach(v FUZZER NAME WORK_DIR SELECTORS DICT SECONDS MAX_LEN)
  if(NOT DEFINED ${v})
    message(FATAL_ERROR "run_fuzz.cmake: -D${v}=... is required")
  endif()
endforeach()
file(REMOVE_RECURSE ${WORK_DIR})
file(MAKE_DIRECTORY ${WORK_DIR}/corpus)
execute_process(COMMAND ${CMAKE_COMMAND} -E env POISE_FUZZ_WRITE_SEEDS=${WORK_DIR}/corpus
                        POISE_FUZZ_SEED_SELECTORS=${SELECTORS} ${FUZZER}
                RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "${NAME}: writing the seed corpus failed (${rc})")
endif()
file(GLOB seeds ${WORK_DIR}/corpus/seed_*)
list(LENGTH seeds n_seeds)
if(n_seeds EQUAL 0)
  message(FATAL_ERROR "${NAME}: no seeds for selectors '${SELECTORS}'")
endif()
# One input may take 120 s before it counts as a hang: the diagnoses (Eigen at -O1 under ASan
# and UBSan, on a loaded CI machine) run 30-40 times slower than the Release build, and some
# tables take about 1 s there (a 44-row table found by the fuzzer: 0.95 s in Release, over 33 s
# here, which the former 30 s limit reported as a hang). A hang still fails the test: it never
# ends. (One such input plus the run's own seconds stays within the test's 300 s.)
# ASan: leaks are not findings here (a refused file may leave static caches); UBSan aborts.
set(ENV{ASAN_OPTIONS} "detect_leaks=0:abort_on_error=0:allocator_may_return_null=0")
set(ENV{UBSAN_OPTIONS} "print_stacktrace=1:halt_on_error=1")
execute_process(COMMAND ${FUZZER} -max_total_time=${SECONDS} -timeout=120 -rss_limit_mb=2048 -malloc_limit_mb=1024
                        -max_len=${MAX_LEN} -dict=${DICT} -artifact_prefix=${WORK_DIR}/ -print_final_stats=1
                        ${WORK_DIR}/corpus
                WORKING_DIRECTORY ${WORK_DIR}
                RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  file(GLOB artifacts ${WORK_DIR}/crash-* ${WORK_DIR}/timeout-* ${WORK_DIR}/oom-* ${WORK_DIR}/leak-*)
  message(FATAL_ERROR "${NAME}: finding (exit ${rc}); input: ${artifacts}\n"
                      "reproduce: ${FUZZER} <input>")
endif()
message(STATUS "${NAME}: no finding in ${SECONDS} s (${n_seeds} seeds)")
