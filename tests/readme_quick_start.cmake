# CTest Readme.QuickStartIsTheExample (registered in tests/CMakeLists.txt):
#   cmake -DREADME=README.md -DEXAMPLE=engine/examples/quick_start.cpp -P readme_quick_start.cmake
# The docs/library-api.md's example must be the compiled and tested quick_start.cpp, byte for
# byte: between the lines `<!-- quick_start.cpp begins -->` and `<!-- quick_start.cpp ends -->`
# it holds a ```cpp fence around the file's text and nothing else.
cmake_minimum_required(VERSION 3.22)

file(READ ${README} readme)
file(READ ${EXAMPLE} example)
set(begin "<!-- quick_start.cpp begins -->\n")
set(end "<!-- quick_start.cpp ends -->\n")
string(FIND "${readme}" "${begin}" at_begin)
string(FIND "${readme}" "${end}" at_end)
if(at_begin EQUAL -1 OR at_end EQUAL -1)
  message(FATAL_ERROR "${README} lacks the line `${begin}` or `${end}`")
endif()
string(LENGTH "${begin}" begin_length)
math(EXPR first "${at_begin} + ${begin_length}")
math(EXPR length "${at_end} - ${first}")
if(length LESS 0)
  message(FATAL_ERROR "${README}: the end marker comes before the begin marker")
endif()
string(SUBSTRING "${readme}" ${first} ${length} block)
set(expected "```cpp\n${example}```\n")
if(NOT block STREQUAL expected)
  file(WRITE ${CMAKE_CURRENT_BINARY_DIR}/readme_quick_start.expected "${expected}")
  file(WRITE ${CMAKE_CURRENT_BINARY_DIR}/readme_quick_start.found "${block}")
  message(FATAL_ERROR "The quick_start block of ${README} differs from ${EXAMPLE}: compare "
          "${CMAKE_CURRENT_BINARY_DIR}/readme_quick_start.found with .expected (diff -u), "
          "then copy the file into ${README} between the markers")
endif()
