# SPDX-License-Identifier: Apache-2.0
# CTest script: run dynblur_calibrate_camera on the 13 real views and check its files.
# -DTOOL=dynblur_calibrate_camera -DDATA=folder with left01..14.jpg (the configure-time default)
# -DWORK=scratch folder. DYNBLUR_TEST_DATA in the environment of the test run wins over DATA.
if(DEFINED ENV{DYNBLUR_TEST_DATA} AND NOT "$ENV{DYNBLUR_TEST_DATA}" STREQUAL "")
  set(DATA "$ENV{DYNBLUR_TEST_DATA}")
endif()
if(NOT EXISTS ${DATA}/left01.jpg)
  # Under the test command (DYNBLUR_REQUIRE_TEST_DATA=1) missing data fails the run.
  if("$ENV{DYNBLUR_REQUIRE_TEST_DATA}" STREQUAL "1")
    message(FATAL_ERROR "test data left01.jpg not found in ${DATA} (DYNBLUR_REQUIRE_TEST_DATA=1: missing data is a "
                        "failure; set DYNBLUR_TEST_DATA)")
  endif()
  # CTest reports the test as skipped on this line (SKIP_REGULAR_EXPRESSION).
  message(STATUS "DYNBLUR-SKIP: test data left01.jpg not found in ${DATA} (set DYNBLUR_TEST_DATA)")
  return()
endif()
set(dir ${WORK}/camera)
file(REMOVE_RECURSE ${dir})
file(MAKE_DIRECTORY ${dir})
execute_process(COMMAND ${TOOL} --board 9x6 --square 0.025 --out ${dir}/cam.xml "${DATA}/left*.jpg"
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
message(STATUS "${out}${err}")
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "exit code ${rc}")
endif()
foreach(f cam.xml cam.yml cam_views.png)
  if(NOT EXISTS ${dir}/${f})
    message(FATAL_ERROR "${f} was not written")
  endif()
endforeach()
file(GLOB leftovers ${dir}/*.tmp*)
if(leftovers)
  message(FATAL_ERROR "temporary files left: ${leftovers}")
endif()
if(NOT out MATCHES "left02.jpg +[0-9]+ +[0-9.]+ +outlier")
  message(FATAL_ERROR "the per-view table does not report left02 as an outlier")
endif()
file(READ ${dir}/cam.yml yml)
if(NOT yml MATCHES "camera_matrix" OR NOT yml MATCHES "distortion_coefficients")
  message(FATAL_ERROR "cam.yml lacks camera_matrix or distortion_coefficients")
endif()
# A board that is not there: a clear message and exit code 1, no file.
execute_process(COMMAND ${TOOL} --board 10x7 --out ${dir}/wrong.xml --no-png ${DATA}/left01.jpg ${DATA}/left03.jpg ${DATA}/left04.jpg
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
message(STATUS "${out}${err}")
if(NOT rc EQUAL 1 OR NOT err MATCHES "INNER corners" OR EXISTS ${dir}/wrong.xml)
  message(FATAL_ERROR "a wrong board size must fail clearly (exit ${rc})")
endif()
