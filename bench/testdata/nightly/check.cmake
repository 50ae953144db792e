# Runs poise_nightly_compare and checks its exit status (exactly EXPECT_EXIT) and that its
# output matches EXPECT_REGEX; both are required, so a check cannot pass vacuously.
#   cmake -DTOOL=... -DARGS="a|b|c" -DEXPECT_EXIT=3 -DEXPECT_REGEX=... [-DWORK_DIR=...] -P check.cmake
foreach(v TOOL ARGS EXPECT_EXIT EXPECT_REGEX)
  if(NOT DEFINED ${v} OR "${${v}}" STREQUAL "")
    message(FATAL_ERROR "check.cmake: ${v} must be given")
  endif()
endforeach()
if(NOT DEFINED WORK_DIR)
  set(WORK_DIR ${CMAKE_CURRENT_BINARY_DIR})
endif()
string(REPLACE "|" ";" _args "${ARGS}")
execute_process(COMMAND ${TOOL} ${_args} WORKING_DIRECTORY ${WORK_DIR}
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
message("${out}${err}")
if(NOT "${rc}" STREQUAL "${EXPECT_EXIT}")
  message(FATAL_ERROR "poise_nightly_compare exited with '${rc}', expected exactly ${EXPECT_EXIT}")
endif()
string(REGEX MATCH "${EXPECT_REGEX}" _match "${out}${err}")
if("${_match}" STREQUAL "")
  message(FATAL_ERROR "the output does not match '${EXPECT_REGEX}'")
endif()
message("exit ${rc} as expected; output matches '${EXPECT_REGEX}'")
