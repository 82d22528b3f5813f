# Runs one example program for a smoke test (see CMakeLists.txt here):
#   cmake -DPROGRAM=exe -DARGS="a;b" -DFOLDER=dir [-DEXPECT_FILE=f] [-DEXPECT_OUTPUT=regex] -P smoke_test.cmake
# Empties FOLDER and runs PROGRAM in it; fails unless the program exits 0, EXPECT_FILE exists
# afterwards and the output matches EXPECT_OUTPUT.

file(REMOVE_RECURSE "${FOLDER}")
file(MAKE_DIRECTORY "${FOLDER}")
execute_process(COMMAND "${PROGRAM}" ${ARGS}
  WORKING_DIRECTORY "${FOLDER}"
  RESULT_VARIABLE result
  OUTPUT_VARIABLE output
  ERROR_VARIABLE errors)
message("${output}${errors}")
if(NOT result EQUAL 0)
  message(FATAL_ERROR "${PROGRAM} exited with ${result}")
endif()
if(DEFINED EXPECT_FILE AND NOT EXISTS "${EXPECT_FILE}")
  message(FATAL_ERROR "${PROGRAM} did not write ${EXPECT_FILE}")
endif()
if(DEFINED EXPECT_OUTPUT AND NOT output MATCHES "${EXPECT_OUTPUT}")
  message(FATAL_ERROR "${PROGRAM}'s output does not match '${EXPECT_OUTPUT}'")
endif()
