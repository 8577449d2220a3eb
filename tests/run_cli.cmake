# Runs the octray CLI once and checks its exit status exactly (CTest's
# WILL_FAIL cannot tell 1 from 2), plus its output.
#   OCTRAY       path of the executable
#   ARGS         arguments separated by "|" (";" does not survive add_test)
#   EXPECT_EXIT  the exact exit status
#   STDOUT_HAS / STDERR_HAS  optional substrings the streams must contain
#   EXPECT_FILE  optional file that must exist afterwards (removed first)
string(REPLACE "|" ";" args "${ARGS}")
if(EXPECT_FILE)
  file(REMOVE "${EXPECT_FILE}")
endif()
execute_process(COMMAND "${OCTRAY}" ${args}
                RESULT_VARIABLE status OUTPUT_VARIABLE out ERROR_VARIABLE err)
set(report "octray ${args}\n  exit: ${status}\n  stdout: ${out}\n  stderr: ${err}")
if(NOT status STREQUAL "${EXPECT_EXIT}")
  message(FATAL_ERROR "expected exit ${EXPECT_EXIT}\n${report}")
endif()
if(DEFINED STDOUT_HAS AND NOT out MATCHES "${STDOUT_HAS}")
  message(FATAL_ERROR "stdout lacks '${STDOUT_HAS}'\n${report}")
endif()
if(DEFINED STDERR_HAS AND NOT err MATCHES "${STDERR_HAS}")
  message(FATAL_ERROR "stderr lacks '${STDERR_HAS}'\n${report}")
endif()
# Failures must say so in exactly one line on stderr (docs/shading-model.md, the scene contract).
if(NOT status EQUAL 0)
  string(REGEX MATCHALL "\n" newlines "${err}")
  list(LENGTH newlines lines)
  if(NOT lines EQUAL 1)
    message(FATAL_ERROR "stderr is not exactly one line\n${report}")
  endif()
endif()
if(EXPECT_FILE AND NOT EXISTS "${EXPECT_FILE}")
  message(FATAL_ERROR "${EXPECT_FILE} was not written\n${report}")
endif()
