# Checks that no public header of the engine (engine/include/dynrt/**) pulls in the SIMD
# wrapper (packet/include/dynrt/packet/simd.h), whose types depend on the instruction set the
# build targets: what a program includes from dynrt must mean the same on every CPU.
#   cmake -DCXX=... -DSOURCE_DIR=... -P public_headers.cmake
file(GLOB_RECURSE headers RELATIVE ${SOURCE_DIR}/engine/include ${SOURCE_DIR}/engine/include/dynrt/*.h)
set(include_flags)
foreach(dir engine/include engine/scene/include anim/include bvh/include packet/include
            tests/reference/include)
  list(APPEND include_flags -I${SOURCE_DIR}/${dir})
endforeach()
set(failed 0)
set(checked 0)
foreach(header ${headers})
  file(WRITE ${CMAKE_CURRENT_BINARY_DIR}/public_header_check.cpp "#include \"${header}\"\n")
  execute_process(
    COMMAND ${CXX} -std=c++20 -M ${include_flags} ${CMAKE_CURRENT_BINARY_DIR}/public_header_check.cpp
    OUTPUT_VARIABLE deps ERROR_VARIABLE errors RESULT_VARIABLE rc)
  math(EXPR checked "${checked} + 1")
  if(NOT rc EQUAL 0)
    message(SEND_ERROR "${header}: does not compile on its own:\n${errors}")
    set(failed 1)
  elseif(deps MATCHES "dynrt/packet/simd[a-z_]*\\.h")
    message(SEND_ERROR "${header}: includes the ISA-dependent SIMD wrapper (${CMAKE_MATCH_0})")
    set(failed 1)
  endif()
endforeach()
if(checked LESS 10)
  message(FATAL_ERROR "only ${checked} public headers found under ${SOURCE_DIR}/engine/include")
endif()
message(STATUS "${checked} public headers checked")
