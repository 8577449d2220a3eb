# fuzz/run_fuzz.cmake — one bounded libFuzzer run (the fuzz.smoke.* tests).
#
#   cmake -DFUZZER=<target binary> -DWORK=<scratch dir> -DRUNS=<n>
#         "-DCORPORA=<dir;dir...>" ["-DARGS=<libFuzzer option;...>"] -P fuzz/run_fuzz.cmake
#
# WORK is emptied and made the first corpus directory, where libFuzzer writes
# what it finds new (the repository's corpora are only read), and the prefix
# of any crash artifact. Fails when libFuzzer reports a crash, a sanitizer
# report, a leak or a timeout (its exit status is then non-zero).
cmake_minimum_required(VERSION 3.21)
foreach(var FUZZER WORK RUNS CORPORA)
  if(NOT DEFINED ${var})
    message(FATAL_ERROR "run_fuzz.cmake: -D${var}=... is required")
  endif()
endforeach()
file(REMOVE_RECURSE "${WORK}")
file(MAKE_DIRECTORY "${WORK}/corpus")
execute_process(
  COMMAND "${FUZZER}" -runs=${RUNS} -seed=19 -timeout=60 -print_final_stats=1
          "-artifact_prefix=${WORK}/" ${ARGS} "${WORK}/corpus" ${CORPORA}
  RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  file(GLOB artifacts "${WORK}/crash-*" "${WORK}/leak-*" "${WORK}/timeout-*" "${WORK}/oom-*")
  message(FATAL_ERROR "run_fuzz.cmake: ${FUZZER} failed (${rc}); inputs: ${artifacts}")
endif()
