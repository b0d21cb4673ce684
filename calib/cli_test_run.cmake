# SPDX-License-Identifier: Apache-2.0
# Shared by the CLI test scripts: run(EXPECTED_EXIT_CODE command args...) runs a command, shows its
# output, fails unless it exits with EXPECTED_EXIT_CODE, and leaves the output in `last_output`.
# (read_timing_file, below, checks and reads what dynblur_calibrate_timing wrote; require_test_data
# finds the test data.)
function(run expected)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  message(STATUS "$ ${ARGN}\n${out}${err}")
  if(NOT rc EQUAL expected)
    message(FATAL_ERROR "exit code ${rc}, expected ${expected}")
  endif()
  set(last_output "${out}${err}" PARENT_SCOPE)
endfunction()

# read_timing_file(DIR): fails unless dynblur_calibrate_timing wrote DIR/timing.yml and its plot
# DIR/timing_objective.png, and sets each numeric field of timing.yml (timeOffset, lineDelayScale, ...)
# as a variable of the caller.
macro(read_timing_file dir)
  foreach(f timing.yml timing_objective.png)
    if(NOT EXISTS ${dir}/${f})
      message(FATAL_ERROR "${f} was not written")
    endif()
  endforeach()
  file(STRINGS ${dir}/timing.yml _timing_lines)
  foreach(_line ${_timing_lines})
    if(_line MATCHES "^([a-zA-Z]+): *([-+0-9.eE]+)$")
      set(${CMAKE_MATCH_1} ${CMAKE_MATCH_2})
    endif()
  endforeach()
endmacro()

# require_test_data(FILE): DATA becomes DYNBLUR_TEST_DATA when the environment sets it. Without
# DATA/FILE the calling script fails under the test command (DYNBLUR_REQUIRE_TEST_DATA=1) or stops,
# reported as skipped (the DYNBLUR-SKIP line matches the tests' SKIP_REGULAR_EXPRESSION). A macro,
# so that its return() leaves the calling script.
macro(require_test_data file)
  if(DEFINED ENV{DYNBLUR_TEST_DATA} AND NOT "$ENV{DYNBLUR_TEST_DATA}" STREQUAL "")
    set(DATA "$ENV{DYNBLUR_TEST_DATA}")
  endif()
  if(NOT EXISTS ${DATA}/${file})
    if("$ENV{DYNBLUR_REQUIRE_TEST_DATA}" STREQUAL "1")
      message(FATAL_ERROR "test data ${file} not found in ${DATA} (DYNBLUR_REQUIRE_TEST_DATA=1: missing data is a "
                          "failure; set DYNBLUR_TEST_DATA)")
    endif()
    message(STATUS "DYNBLUR-SKIP: test data ${file} not found in ${DATA} (set DYNBLUR_TEST_DATA)")
    return()
  endif()
endmacro()
