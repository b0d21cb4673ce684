# SPDX-License-Identifier: Apache-2.0
# Shared by the CLI test scripts: run(EXPECTED_EXIT_CODE command args...) runs a command, shows its
# output, fails unless it exits with EXPECTED_EXIT_CODE, and leaves the output in `last_output`.
# (Below: expect checks that output, expect_written, read_yaml_numbers and read_timing_file check and read what a program wrote;
# require_test_data finds the test data; run_rehearsal runs a document's rehearsal block;
# start_actuator_sim and stop_actuator_sim run the actuator simulator in the background.)
function(run expected)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  message(STATUS "$ ${ARGN}\n${out}${err}")
  if(NOT rc EQUAL expected)
    message(FATAL_ERROR "exit code ${rc}, expected ${expected}")
  endif()
  set(last_output "${out}${err}" PARENT_SCOPE)
endfunction()

# expect(PATTERN WHAT): fails with WHAT unless the last run's output matches PATTERN.
function(expect pattern what)
  if(NOT last_output MATCHES "${pattern}")
    message(FATAL_ERROR "${what}: the message does not match '${pattern}'")
  endif()
endfunction()

# expect_written(DIR WHO FILE...): fails unless WHO (a program, a step) wrote each FILE under DIR.
function(expect_written dir who)
  foreach(f ${ARGN})
    if(NOT EXISTS ${dir}/${f})
      message(FATAL_ERROR "${who} did not write ${f}")
    endif()
  endforeach()
endfunction()

# read_yaml_numbers(FILE): sets each "name: number" line of FILE (a plant, mount or timing file) as a
# variable of the caller.
macro(read_yaml_numbers file)
  file(STRINGS ${file} _yaml_lines)
  foreach(_line ${_yaml_lines})
    if(_line MATCHES "^([a-zA-Z][a-zA-Z0-9_]*): *([-+0-9.eE]+)$")
      set(${CMAKE_MATCH_1} ${CMAKE_MATCH_2})
    endif()
  endforeach()
endmacro()

# read_timing_file(DIR): fails unless dynblur_calibrate_timing wrote DIR/timing.yml and its plot
# DIR/timing_objective.png, and sets each numeric field of timing.yml (timeOffset, lineDelayScale, ...)
# as a variable of the caller.
macro(read_timing_file dir)
  expect_written(${dir} dynblur_calibrate_timing timing.yml timing_objective.png)
  read_yaml_numbers(${dir}/timing.yml)
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

# run_rehearsal(DOC): runs the block of DOC between its <!-- rehearsal --> markers (a ```sh fence) as the
# document writes it, in order, under bash -e, in WORK, with BIN and CALIB (the programs' folders) first
# on the PATH and DATA in the environment; fails when a command fails. The output is left in
# `last_output`.
function(run_rehearsal doc)
  file(READ ${doc} text)
  string(FIND "${text}" "<!-- rehearsal -->" begin)
  string(FIND "${text}" "<!-- /rehearsal -->" end)
  if(begin EQUAL -1 OR end EQUAL -1)
    message(FATAL_ERROR "${doc} has no <!-- rehearsal --> block")
  endif()
  math(EXPR length "${end} - ${begin}")
  string(SUBSTRING "${text}" ${begin} ${length} block)
  string(REGEX REPLACE "<!-- rehearsal -->[^\n]*\n```sh\n" "" block "${block}")
  string(REGEX REPLACE "```\n$" "" block "${block}")
  file(WRITE ${WORK}/rehearsal.sh "set -euo pipefail\nset -x\n${block}")
  execute_process(COMMAND env "PATH=${BIN}:${CALIB}:$ENV{PATH}" "DATA=${DATA}" bash ${WORK}/rehearsal.sh
                  WORKING_DIRECTORY ${WORK} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  message(STATUS "${out}${err}")
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "the rehearsal of ${doc} failed (exit ${rc})")
  endif()
  set(last_output "${out}${err}" PARENT_SCOPE)
endfunction()

# start_actuator_sim(DIR URI_VAR SIMULATOR ARGS...): starts the actuator simulator in the background
# (execute_process cannot leave a process running: a shell starts it, its output in DIR/sim.txt, its
# pid in DIR/sim.pid) on a free TCP port, waits for its URI and sets URI_VAR to it; fails when it
# prints none. Every ARG is passed quoted.
function(start_actuator_sim dir uri_var simulator)
  set(args "")
  foreach(arg ${ARGN})
    string(APPEND args " '${arg}'")
  endforeach()
  execute_process(COMMAND sh -c "'${simulator}'${args} --tcp-port 0 > '${dir}/sim.txt' 2>&1 & echo $! > '${dir}/sim.pid'")
  foreach(i RANGE 100)
    file(READ ${dir}/sim.txt sim)
    if(sim MATCHES "\\(uri (tcp://[^)]*)\\)")
      set(${uri_var} ${CMAKE_MATCH_1} PARENT_SCOPE)
      return()
    endif()
    execute_process(COMMAND sleep 0.1)
  endforeach()
  message(FATAL_ERROR "the actuator simulator did not start: ${sim}")
endfunction()

# stop_actuator_sim(DIR): ends the simulator start_actuator_sim(DIR ...) started.
function(stop_actuator_sim dir)
  file(READ ${dir}/sim.pid pid)
  string(STRIP "${pid}" pid)
  execute_process(COMMAND kill ${pid})
endfunction()
