# SPDX-License-Identifier: Apache-2.0
# CTest script: simulate a log, identify it with the CLI, check the exit codes and the plant file.
# -DTOOL=dynblur_identify_plant -DSIM=(same tool, --simulate) -DWORK=scratch folder
file(REMOVE_RECURSE ${WORK}/plant)
file(MAKE_DIRECTORY ${WORK}/plant)
set(dir ${WORK}/plant)

include(${CMAKE_CURRENT_LIST_DIR}/cli_test_run.cmake)

# 11.3 Hz, zeta 0.08, 0.75 deg/level, step to level 5 logged at 37.3 ms but moving 12.3 ms later
# (an unknown start), 0.02 deg noise.
run(0 ${SIM} --simulate ${dir}/log.csv --hz 11.3 --zeta 0.08 --gain-deg 0.75 --step-level 5 --delay 0.0373
    --latency 0.0123 --noise-deg 0.02 --seed 7)
run(0 ${TOOL} ${dir}/log.csv --out ${dir}/plant.yml --max-level 12)
if(NOT last_output MATCHES "delay +1[12]\\.[0-9]+ ms")
  message(FATAL_ERROR "the 12.3 ms delay is not found")
endif()
expect_written(${dir} dynblur_identify_plant plant.yml plant_fit.png)
read_yaml_numbers(${dir}/plant.yml)
message(STATUS "plant file: naturalFreqHz=${naturalFreqHz} dampingRatio=${dampingRatio} gain=${gain} maxLevel=${maxLevel}")
# A field the file lacks (or whose value is no number) must fail: CMake's LESS and GREATER are false
# for an undefined variable, so the range checks below would pass it.
foreach(field naturalFreqHz dampingRatio gain maxLevel)
  if(NOT DEFINED ${field})
    message(FATAL_ERROR "plant.yml has no numeric field ${field}")
  endif()
endforeach()
# CMake has no floating-point comparison beyond VERSION-free LESS/GREATER on decimals: bound them.
if(naturalFreqHz LESS 11.2 OR naturalFreqHz GREATER 11.4)
  message(FATAL_ERROR "naturalFreqHz ${naturalFreqHz} not within 11.3 +- 0.1")
endif()
if(dampingRatio LESS 0.075 OR dampingRatio GREATER 0.085)
  message(FATAL_ERROR "dampingRatio ${dampingRatio} not within 0.08 +- 0.005")
endif()
# 0.75 deg = 0.0130900 rad
if(gain LESS 0.01302 OR gain GREATER 0.01316)
  message(FATAL_ERROR "gain ${gain} not within 0.5% of 0.0130900 rad/level")
endif()
if(NOT maxLevel EQUAL 12)
  message(FATAL_ERROR "maxLevel ${maxLevel} != 12")
endif()

# Refusals: missing file, garbage line, no motion, too few samples; nothing written.
run(1 ${TOOL} ${dir}/absent.csv --out ${dir}/bad.yml --no-png)
file(WRITE ${dir}/garbage.csv "t,theta,level\n0,0,0\n0.001,abc,1\n")
run(1 ${TOOL} ${dir}/garbage.csv --out ${dir}/bad.yml --no-png)
if(NOT last_output MATCHES "garbage.csv:3:")
  message(FATAL_ERROR "the malformed line is not named")
endif()
run(0 ${SIM} --simulate ${dir}/still.csv --step-level 0 --noise-deg 0.01)
run(1 ${TOOL} ${dir}/still.csv --out ${dir}/bad.yml --no-png)
if(NOT last_output MATCHES "no motion")
  message(FATAL_ERROR "no motion is not reported")
endif()
run(0 ${SIM} --simulate ${dir}/short.csv --duration 0.01)
run(1 ${TOOL} ${dir}/short.csv --out ${dir}/bad.yml --no-png)
if(NOT last_output MATCHES "at least 20")
  message(FATAL_ERROR "too few samples is not reported")
endif()
if(EXISTS ${dir}/bad.yml)
  message(FATAL_ERROR "a plant file was written for a bad log")
endif()
run(2 ${TOOL} ${dir}/log.csv --bogus)
run(0 ${TOOL} --help)
