# CTest Docs.ApiReferenceIsComplete (registered in tests/CMakeLists.txt):
#   cmake -DDOXYGEN=doxygen -DSOURCE=<repo> -DOUT=<dir> -P docs_api_reference.cmake
# Generates the library API's reference from its public headers with docs/Doxyfile and fails on
# any warning Doxygen gives: a public class, member, function or enumerator without
# documentation, or a reference that does not resolve (issue 37).
cmake_minimum_required(VERSION 3.22)
file(REMOVE_RECURSE ${OUT})
file(MAKE_DIRECTORY ${OUT})
set(ENV{DYNRT_DOCS_OUT} ${OUT})
execute_process(COMMAND ${DOXYGEN} docs/Doxyfile WORKING_DIRECTORY ${SOURCE} RESULT_VARIABLE status)
if(NOT status EQUAL 0)
  message(FATAL_ERROR "doxygen failed (${status})")
endif()
file(READ ${OUT}/doxygen-warnings.log warnings)
if(NOT warnings STREQUAL "")
  message(FATAL_ERROR "Doxygen warns about the library API's headers:\n${warnings}")
endif()
if(NOT EXISTS ${OUT}/api/classdynrt_1_1Engine.html)
  message(FATAL_ERROR "Doxygen made no page for dynrt::Engine in ${OUT}/api")
endif()
message(STATUS "API reference complete: ${OUT}/api/index.html")
