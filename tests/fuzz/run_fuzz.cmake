# ctest driver of fuzz_study_parser: writes the seed corpus to a fresh folder of the build
# tree (the repository's files are never modified), then fuzzes for SECONDS seconds.
# Variables: FUZZER, WORK_DIR, DICT, SECONDS. A finding (crash, sanitizer report, timeout of
# one input, out-of-memory, uncaught exception) fails the test and leaves the input that
# caused it in WORK_DIR (crash-*, timeout-*, oom-*); reproduce with `FUZZER <that file>`.
foreach(v FUZZER WORK_DIR DICT SECONDS)
  if(NOT DEFINED ${v})
    message(FATAL_ERROR "run_fuzz.cmake: -D${v}=... is required")
  endif()
endforeach()
file(REMOVE_RECURSE ${WORK_DIR})
file(MAKE_DIRECTORY ${WORK_DIR}/corpus)
execute_process(COMMAND ${CMAKE_COMMAND} -E env POISE_FUZZ_WRITE_SEEDS=${WORK_DIR}/corpus ${FUZZER}
                RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "fuzz_study_parser: writing the seed corpus failed (${rc})")
endif()
# ASan: leaks are not findings here (a refused file may leave static caches); UBSan aborts.
set(ENV{ASAN_OPTIONS} "detect_leaks=0:abort_on_error=0:allocator_may_return_null=0")
set(ENV{UBSAN_OPTIONS} "print_stacktrace=1:halt_on_error=1")
execute_process(COMMAND ${FUZZER} -max_total_time=${SECONDS} -timeout=10 -rss_limit_mb=2048 -malloc_limit_mb=1024
                        -max_len=65536 -dict=${DICT} -artifact_prefix=${WORK_DIR}/ -print_final_stats=1
                        ${WORK_DIR}/corpus
                WORKING_DIRECTORY ${WORK_DIR}
                RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  file(GLOB artifacts ${WORK_DIR}/crash-* ${WORK_DIR}/timeout-* ${WORK_DIR}/oom-* ${WORK_DIR}/leak-*)
  message(FATAL_ERROR "fuzz_study_parser: finding (exit ${rc}); input: ${artifacts}\n"
                      "reproduce: ${FUZZER} <input>")
endif()
message(STATUS "fuzz_study_parser: no finding in ${SECONDS} s")
