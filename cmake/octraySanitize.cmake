# cmake/octraySanitize.cmake — OCTRAY_SANITIZE and OCTRAY_FUZZ: instrument every
# target of this build (library, tools, tests) for the sanitizers, or for
# libFuzzer (tools/check builds each in a tree of its own).
#
#   -DOCTRAY_SANITIZE=address,undefined   ASan + UBSan (GCC or Clang; GCC's
#                                         UBSan checks float-to-int overflow only
#                                         with float-cast-overflow added)
#   -DOCTRAY_SANITIZE=thread              TSan
#   -DOCTRAY_FUZZ=ON                      fuzz/ targets, libFuzzer: Clang only;
#                                         tools/check combines it with
#                                         OCTRAY_SANITIZE=address,undefined
#
# Any report is fatal (-fno-sanitize-recover=all): a test that triggers one
# fails. Included before the first target so the options reach them all.
set(OCTRAY_SANITIZE "" CACHE STRING
    "Sanitizers for every target: address,undefined or thread (empty: none)")
option(OCTRAY_FUZZ "Build the libFuzzer targets in fuzz/ (Clang only)" OFF)

if(OCTRAY_SANITIZE)
  string(REPLACE "," ";" octray_sanitizers "${OCTRAY_SANITIZE}")
  foreach(s IN LISTS octray_sanitizers)
    if(NOT s MATCHES "^(address|undefined|thread|float-cast-overflow)$")
      message(FATAL_ERROR "OCTRAY_SANITIZE: unknown sanitizer '${s}' (address, undefined, thread, float-cast-overflow)")
    endif()
  endforeach()
  if("thread" IN_LIST octray_sanitizers AND "address" IN_LIST octray_sanitizers)
    message(FATAL_ERROR "OCTRAY_SANITIZE: thread and address cannot be combined")
  endif()
  add_compile_options(-fsanitize=${OCTRAY_SANITIZE} -fno-sanitize-recover=all -fno-omit-frame-pointer)
  add_link_options(-fsanitize=${OCTRAY_SANITIZE})
  message(STATUS "octray: sanitizers ${OCTRAY_SANITIZE}")
endif()

if(OCTRAY_FUZZ)
  if(NOT CMAKE_CXX_COMPILER_ID MATCHES "Clang")
    message(FATAL_ERROR "OCTRAY_FUZZ needs Clang (libFuzzer): configure with CXX=clang++")
  endif()
  # Coverage feedback from every target; the fuzz executables link libFuzzer's main.
  add_compile_options(-fsanitize=fuzzer-no-link)
endif()
