# The installable package of the library API (docs/library-api.md "Library API"): `cmake --install BUILD
# --prefix P` puts into P
#   lib/libdynrt.so*                      the shared library (target dynrt_api)
#   include/dynrt/dynrt.h, api/*.h,       the public API headers and nothing else: the engine's
#     engine/frame_stats.h,                 other headers stay private to this tree
#     engine/texture_figures.h,
#     engine/render_progress.h
#   lib/cmake/dynrt/dynrt*.cmake          find_package(dynrt), imported target dynrt::dynrt
#   lib/pkgconfig/dynrt.pc                pkg-config --cflags --libs dynrt
# Only the library is installed: the CLI, tests and benchmarks run from the build tree.
# tests/external_project/ builds a program against an installed copy (CTest
# ExternalProject.FindPackageAndPkgConfig).

include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

set(DYNRT_INSTALL_CMAKEDIR ${CMAKE_INSTALL_LIBDIR}/cmake/dynrt)

# Consumers link dynrt::dynrt in both trees: the alias here, the exported name when installed.
set_target_properties(dynrt_api PROPERTIES EXPORT_NAME dynrt)
install(TARGETS dynrt_api EXPORT dynrtTargets
  LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR})

set(_dynrt_headers ${PROJECT_SOURCE_DIR}/engine/include/dynrt)
install(FILES ${_dynrt_headers}/dynrt.h DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/dynrt)
# Everything under api/ is public by definition; of engine/, only what the API's types use.
install(DIRECTORY ${_dynrt_headers}/api DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/dynrt
  FILES_MATCHING PATTERN "*.h")
install(FILES ${_dynrt_headers}/engine/frame_stats.h ${_dynrt_headers}/engine/texture_figures.h
  ${_dynrt_headers}/engine/render_progress.h DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/dynrt/engine)

# ---- CMake package: find_package(dynrt) ------------------------------------------------------
install(EXPORT dynrtTargets NAMESPACE dynrt:: DESTINATION ${DYNRT_INSTALL_CMAKEDIR})
configure_package_config_file(${CMAKE_CURRENT_LIST_DIR}/dynrtConfig.cmake.in
  ${PROJECT_BINARY_DIR}/dynrtConfig.cmake
  INSTALL_DESTINATION ${DYNRT_INSTALL_CMAKEDIR})
# 0.x: the API may still change between minor versions; SameMajorVersion follows the SONAME.
write_basic_package_version_file(${PROJECT_BINARY_DIR}/dynrtConfigVersion.cmake
  VERSION ${PROJECT_VERSION} COMPATIBILITY SameMajorVersion)
install(FILES ${PROJECT_BINARY_DIR}/dynrtConfig.cmake ${PROJECT_BINARY_DIR}/dynrtConfigVersion.cmake
  DESTINATION ${DYNRT_INSTALL_CMAKEDIR})

# ---- pkg-config: dynrt.pc --------------------------------------------------------------------
# The file names its prefix, which is known only at install time (`cmake --install --prefix P`):
# it is written here with the placeholder @DYNRT_INSTALL_PREFIX@, installed, then the installed
# copy gets the prefix (DESTDIR stays out of it, as for a staged package).
set(DYNRT_PC_PREFIX "@DYNRT_INSTALL_PREFIX@")
foreach(_dir LIBDIR INCLUDEDIR)
  if(IS_ABSOLUTE "${CMAKE_INSTALL_${_dir}}")
    set(DYNRT_PC_${_dir} "${CMAKE_INSTALL_${_dir}}")
  else()
    set(DYNRT_PC_${_dir} "\${prefix}/${CMAKE_INSTALL_${_dir}}")
  endif()
endforeach()
# A sanitizer build of libdynrt needs programs linked with the same runtime (engine/CMakeLists).
set(DYNRT_PC_LIBS_EXTRA "")
if(DYNRT_SANITIZE)
  set(DYNRT_PC_LIBS_EXTRA " -fsanitize=address,undefined")
endif()
configure_file(${CMAKE_CURRENT_LIST_DIR}/dynrt.pc.in ${PROJECT_BINARY_DIR}/dynrt.pc @ONLY)
install(FILES ${PROJECT_BINARY_DIR}/dynrt.pc DESTINATION ${CMAKE_INSTALL_LIBDIR}/pkgconfig)
if(IS_ABSOLUTE "${CMAKE_INSTALL_LIBDIR}")
  set(_dynrt_pc_dir "${CMAKE_INSTALL_LIBDIR}/pkgconfig")
else()
  set(_dynrt_pc_dir "\${CMAKE_INSTALL_PREFIX}/${CMAKE_INSTALL_LIBDIR}/pkgconfig")
endif()
install(CODE "
  set(DYNRT_INSTALL_PREFIX \"\${CMAKE_INSTALL_PREFIX}\")
  configure_file(\"${PROJECT_BINARY_DIR}/dynrt.pc\"
                 \"\$ENV{DESTDIR}${_dynrt_pc_dir}/dynrt.pc\" @ONLY)
")
