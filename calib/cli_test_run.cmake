# SPDX-License-Identifier: Apache-2.0
# Shared by the CLI test scripts: run(EXPECTED_EXIT_CODE command args...) runs a command, shows its
# output, fails unless it exits with EXPECTED_EXIT_CODE, and leaves the output in `last_output`.
function(run expected)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  message(STATUS "$ ${ARGN}\n${out}${err}")
  if(NOT rc EQUAL expected)
    message(FATAL_ERROR "exit code ${rc}, expected ${expected}")
  endif()
  set(last_output "${out}${err}" PARENT_SCOPE)
endfunction()
