# SPDX-License-Identifier: Apache-2.0
# CTest script: run dynblur_calibrate_camera on the 13 real views and check its files.
# -DTOOL=dynblur_calibrate_camera -DDATA=folder with left01..14.jpg (the configure-time default)
# -DWORK=scratch folder. DYNBLUR_TEST_DATA in the environment of the test run wins over DATA.
include(${CMAKE_CURRENT_LIST_DIR}/cli_test_run.cmake)
require_test_data(left01.jpg)
set(dir ${WORK}/camera)
file(REMOVE_RECURSE ${dir})
file(MAKE_DIRECTORY ${dir})
execute_process(COMMAND ${TOOL} --board 9x6 --square 0.025 --out ${dir}/cam.xml "${DATA}/left*.jpg"
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
message(STATUS "${out}${err}")
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "exit code ${rc}")
endif()
expect_written(${dir} dynblur_calibrate_camera cam.xml cam.yml cam_views.png)
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
