# tests/install_consumer.cmake — install octray into a temporary prefix, then
# configure, build and run examples/consumer against that prefix only.
#
#   cmake -DOCTRAY_BINARY_DIR=<octray build> -DCONSUMER_SOURCE_DIR=<examples/consumer>
#         -DWORK_DIR=<scratch dir> [-DCONFIG=<build configuration>] [-DGENERATOR=<generator>]
#         [-DCXX_COMPILER=<c++>] [-DXSIMD_DIR=<dir of xsimdConfig.cmake>]
#         -P tests/install_consumer.cmake
#
# Checks, in order: `cmake --install` succeeds; the prefix holds the umbrella
# header, the library and the package files; the exported target carries no
# compile options or definitions (nothing leaks into a consumer); the consumer
# finds octray in the temporary prefix (not in the source or build tree),
# builds with -Wall -Wextra -Werror, and runs with exit status 0.
cmake_minimum_required(VERSION 3.21)

foreach(var OCTRAY_BINARY_DIR CONSUMER_SOURCE_DIR WORK_DIR)
  if(NOT DEFINED ${var})
    message(FATAL_ERROR "install_consumer.cmake: -D${var}=... is required")
  endif()
endforeach()
# CONFIG is the build's configuration ($<CONFIG>), empty for a single-config
# build without CMAKE_BUILD_TYPE: then install that build as it is.
set(config_args "")
set(consumer_type Release)
if(CONFIG)
  set(config_args --config "${CONFIG}")
  set(consumer_type "${CONFIG}")
endif()

set(prefix "${WORK_DIR}/prefix")
set(build "${WORK_DIR}/build")
file(REMOVE_RECURSE "${WORK_DIR}")
file(MAKE_DIRECTORY "${WORK_DIR}")

function(run step)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "install.consumer: ${step} failed (${rc})\n$ ${ARGN}\n${out}\n${err}")
  endif()
  message(STATUS "${step}: ok")
  set(last_output "${out}" PARENT_SCOPE)
endfunction()

# 1. Install into the temporary prefix.
run("install" "${CMAKE_COMMAND}" --install "${OCTRAY_BINARY_DIR}" --prefix "${prefix}" ${config_args})

# 2. What must be there. The package directory is lib/ or lib64/ (GNUInstallDirs).
file(GLOB config_file "${prefix}/lib*/cmake/octray/octrayConfig.cmake")
file(GLOB targets_file "${prefix}/lib*/cmake/octray/octrayTargets.cmake")
file(GLOB library "${prefix}/lib*/*octray.*")
if(library)
  list(GET library 0 library)
endif()
foreach(f "${prefix}/include/octray/octray.hpp" "${prefix}/include/octray/kernels.hpp" "${config_file}"
          "${targets_file}" "${library}")
  if(f STREQUAL "" OR NOT EXISTS "${f}")
    message(FATAL_ERROR "install.consumer: missing from the install: '${f}' (prefix ${prefix})")
  endif()
endforeach()
get_filename_component(package_dir "${config_file}" DIRECTORY)

# 3. Nothing but include directory, C++17 and xsimd may reach a consumer.
file(READ "${targets_file}" targets)
string(REGEX MATCHALL "INTERFACE_[A-Z_]+ \"[^\"]*\"" props "${targets}")
foreach(p IN LISTS props)
  if(p MATCHES "^INTERFACE_(COMPILE_OPTIONS|COMPILE_DEFINITIONS|LINK_OPTIONS)"
     OR p MATCHES "octray_warnings|-W|-m[a-z]|-f[a-z]")
    message(FATAL_ERROR "install.consumer: the exported octray::octray passes a build-only flag "
                        "or target to consumers: ${p}")
  endif()
endforeach()
if(NOT props MATCHES "INTERFACE_INCLUDE_DIRECTORIES")
  message(FATAL_ERROR "install.consumer: unexpected octrayTargets.cmake (no INTERFACE_INCLUDE_DIRECTORIES):\n${targets}")
endif()

# 4. Configure the consumer against the prefix only, with strict warnings.
set(configure_args -S "${CONSUMER_SOURCE_DIR}" -B "${build}" "-DCMAKE_PREFIX_PATH=${prefix}"
    "-DCMAKE_BUILD_TYPE=${consumer_type}" "-DCMAKE_CXX_FLAGS=-Wall -Wextra -Werror")
if(GENERATOR)
  list(APPEND configure_args -G "${GENERATOR}")
endif()
if(CXX_COMPILER)
  list(APPEND configure_args "-DCMAKE_CXX_COMPILER=${CXX_COMPILER}")
endif()
if(XSIMD_DIR)
  list(APPEND configure_args "-Dxsimd_DIR=${XSIMD_DIR}")
endif()
run("configure consumer" "${CMAKE_COMMAND}" ${configure_args})

file(STRINGS "${build}/CMakeCache.txt" found_dir REGEX "^octray_DIR:")
string(REGEX REPLACE "^octray_DIR:[A-Z]+=" "" found_dir "${found_dir}")
get_filename_component(found_dir "${found_dir}" REALPATH)
get_filename_component(package_dir "${package_dir}" REALPATH)
if(NOT found_dir STREQUAL package_dir)
  message(FATAL_ERROR "install.consumer: the consumer found octray in '${found_dir}', not in the install '${package_dir}'")
endif()

# 5. Build and run it.
run("build consumer" "${CMAKE_COMMAND}" --build "${build}" --config "${consumer_type}")
find_program(app NAMES app PATHS "${build}" "${build}/${consumer_type}" NO_DEFAULT_PATH)
if(NOT app)
  message(FATAL_ERROR "install.consumer: no 'app' executable in ${build}")
endif()
run("run consumer" "${app}")
message(STATUS "consumer says: ${last_output}")
