# CTest ExternalProject.FindPackageAndPkgConfig (registered in tests/CMakeLists.txt):
#   cmake -DBUILD_DIR=... -DSOURCE_DIR=... -DWORK_DIR=... -DLIBDIR=... -DINCLUDEDIR=...
#         -DCXX=... -DGENERATOR=... -P check_install.cmake
# Installs the built tree BUILD_DIR into WORK_DIR/prefix, checks that only the public headers
# went in, then builds engine/examples/quick_start.cpp against the prefix twice, as an outside
# program would: with find_package(dynrt) (tests/external_project/CMakeLists.txt) and with
# `c++ $(pkg-config --cflags --libs dynrt)`. Each program must run and exit 0. Needs libdynrt
# built first (the test runs after the build; `cmake --install` builds nothing).
cmake_minimum_required(VERSION 3.22)

foreach(var BUILD_DIR SOURCE_DIR WORK_DIR LIBDIR INCLUDEDIR CXX GENERATOR)
  if(NOT DEFINED ${var})
    message(FATAL_ERROR "check_install.cmake: -D${var}=... is missing")
  endif()
endforeach()

# Runs a command, echoing it; any failure fails the test with the command's output.
function(run what)
  cmake_parse_arguments(PARSE_ARGV 1 ARG "" "WORKING_DIRECTORY" "COMMAND")
  if(NOT ARG_WORKING_DIRECTORY)
    set(ARG_WORKING_DIRECTORY ${WORK_DIR})
  endif()
  string(JOIN " " shown ${ARG_COMMAND})
  message(STATUS "${what}: ${shown}")
  execute_process(COMMAND ${ARG_COMMAND} WORKING_DIRECTORY ${ARG_WORKING_DIRECTORY}
                  RESULT_VARIABLE result OUTPUT_VARIABLE output ERROR_VARIABLE output)
  if(NOT result EQUAL 0)
    message(FATAL_ERROR "${what} failed (${result}):\n${output}")
  endif()
  message(STATUS "${output}")
endfunction()

set(prefix ${WORK_DIR}/prefix)
file(REMOVE_RECURSE ${WORK_DIR})
file(MAKE_DIRECTORY ${WORK_DIR})
# The install goes under `prefix` exactly: no DESTDIR from the caller's environment.
unset(ENV{DESTDIR})
run("install" COMMAND ${CMAKE_COMMAND} --install ${BUILD_DIR} --prefix ${prefix})

# ---- Only the API's headers are installed ----
file(GLOB_RECURSE headers RELATIVE ${prefix}/${INCLUDEDIR} ${prefix}/${INCLUDEDIR}/*)
foreach(header IN LISTS headers)
  if(NOT header MATCHES "^dynrt/(dynrt\\.h|api/[a-z_]+\\.h|engine/frame_stats\\.h|engine/texture_figures\\.h|engine/render_progress\\.h)$")
    message(FATAL_ERROR "installed a header that is not part of the API: ${header}")
  endif()
endforeach()
foreach(required dynrt/dynrt.h dynrt/api/engine.h dynrt/engine/frame_stats.h dynrt/engine/texture_figures.h
                 dynrt/engine/render_progress.h)
  if(NOT EXISTS ${prefix}/${INCLUDEDIR}/${required})
    message(FATAL_ERROR "the install lacks ${required}")
  endif()
endforeach()

set(example ${SOURCE_DIR}/engine/examples/quick_start.cpp)

# ---- 1. CMake: find_package(dynrt), target_link_libraries(... dynrt::dynrt) ----
run("configure the outside project" COMMAND ${CMAKE_COMMAND}
    -S ${SOURCE_DIR}/tests/external_project -B ${WORK_DIR}/cmake-build -G ${GENERATOR}
    -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_COMPILER=${CXX} -DCMAKE_PREFIX_PATH=${prefix}
    -DQUICK_START_SOURCE=${example})
run("build the outside project" COMMAND ${CMAKE_COMMAND} --build ${WORK_DIR}/cmake-build)
file(MAKE_DIRECTORY ${WORK_DIR}/run-cmake)
run("run the find_package build" COMMAND ${WORK_DIR}/cmake-build/quick_start
    WORKING_DIRECTORY ${WORK_DIR}/run-cmake)
if(NOT EXISTS ${WORK_DIR}/run-cmake/quick_start.png)
  message(FATAL_ERROR "the find_package build wrote no quick_start.png")
endif()

# ---- 2. pkg-config: c++ -std=c++20 quick_start.cpp $(pkg-config --cflags --libs dynrt) ----
find_program(PKG_CONFIG NAMES pkg-config pkgconf REQUIRED)
set(ENV{PKG_CONFIG_PATH} ${prefix}/${LIBDIR}/pkgconfig)
execute_process(COMMAND ${PKG_CONFIG} --cflags --libs dynrt RESULT_VARIABLE result
                OUTPUT_VARIABLE flags ERROR_VARIABLE flags OUTPUT_STRIP_TRAILING_WHITESPACE)
if(NOT result EQUAL 0)
  message(FATAL_ERROR "pkg-config --cflags --libs dynrt failed:\n${flags}")
endif()
execute_process(COMMAND ${PKG_CONFIG} --variable=libdir dynrt OUTPUT_VARIABLE libdir
                OUTPUT_STRIP_TRAILING_WHITESPACE)
separate_arguments(flags UNIX_COMMAND "${flags}")
# The prefix is not on the loader's path, so the program records it (as CMake does above).
run("build with pkg-config" COMMAND ${CXX} -std=c++20 ${example} ${flags} -Wl,-rpath,${libdir}
    -o ${WORK_DIR}/quick_start_pkg_config)
file(MAKE_DIRECTORY ${WORK_DIR}/run-pkg-config)
run("run the pkg-config build" COMMAND ${WORK_DIR}/quick_start_pkg_config
    WORKING_DIRECTORY ${WORK_DIR}/run-pkg-config)
if(NOT EXISTS ${WORK_DIR}/run-pkg-config/quick_start.png)
  message(FATAL_ERROR "the pkg-config build wrote no quick_start.png")
endif()
