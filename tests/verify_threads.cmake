# `octray verify --threads 0` runs on all cores (OpenMP's count, set here by
# OMP_NUM_THREADS=3) and reports exactly what `--threads 1` reports: rows are
# rendered independently, so the tables must be identical.
#   OCTRAY  path of the executable
#   SCENE   scene file
set(ENV{OMP_NUM_THREADS} 3)
foreach(n 0 1)
  execute_process(COMMAND "${OCTRAY}" verify "${SCENE}" --threads ${n}
                  RESULT_VARIABLE status_${n} OUTPUT_VARIABLE out_${n} ERROR_VARIABLE err_${n})
  if(NOT status_${n} EQUAL 0)
    message(FATAL_ERROR "octray verify --threads ${n}: exit ${status_${n}}\n${out_${n}}${err_${n}}")
  endif()
endforeach()
if(NOT out_0 MATCHES "packet renders on 3 threads\n")
  message(FATAL_ERROR "--threads 0 with OMP_NUM_THREADS=3 did not use 3 threads:\n${out_0}")
endif()
if(NOT out_1 MATCHES "packet renders on 1 thread\n")
  message(FATAL_ERROR "--threads 1 did not use 1 thread:\n${out_1}")
endif()
string(REGEX REPLACE "packet renders on [0-9]+ threads?\n" "" table_0 "${out_0}")
string(REGEX REPLACE "packet renders on [0-9]+ threads?\n" "" table_1 "${out_1}")
if(NOT table_0 STREQUAL table_1)
  message(FATAL_ERROR "--threads 0 and --threads 1 report differently:\n${out_0}\n---\n${out_1}")
endif()
