# SPDX-License-Identifier: Apache-2.0
# CTest script: dynblur_actuator_sim --axes 3 with a plant file per axis and a drifted truth, driven by
# dynblur_actuator_ctl with one --schedule per axis (every axis verified, one START, per-axis status);
# and the refusals: a schedule count that is not the controller's, a bad schedule on one axis (nothing
# starts), --upload with --schedule, a --drift-wn of the wrong length.
# -DBIN=build/samples -DWORK=scratch folder
set(dir ${WORK}/actuator_axes)
file(REMOVE_RECURSE ${dir})
file(MAKE_DIRECTORY ${dir})
include(${CMAKE_CURRENT_LIST_DIR}/cli_test_run.cmake)

function(write_schedule name levels)
  file(WRITE ${dir}/${name}.yml "%YAML:1.0\n---\ntimes: [ 0.0, 0.0113, 0.0262, 0.04 ]\nlevels: [ ${levels} ]\ninitialLevel: 0\n")
endfunction()
write_schedule(pan "4, 10, 7, 10")
write_schedule(tilt "-2, -5, -4, -5")
write_schedule(roll "1, 3, 2, 3")
write_schedule(bad "1, 30, 2, 3")
file(WRITE ${dir}/pan_plant.yml "%YAML:1.0\n---\nnaturalFreqHz: 14.4\ndampingRatio: 0.12\ngain: 0.0174533\nmaxLevel: 16\n")
file(WRITE ${dir}/tilt_plant.yml "%YAML:1.0\n---\nnaturalFreqHz: 9.0\ndampingRatio: 0.2\ngain: 0.00872665\nmaxLevel: 12\n")

# The simulator's own refusals, at once.
run(2 ${BIN}/dynblur_actuator_sim --axes 2 --drift-wn 0.03 --max-seconds 1)
expect("--drift-wn has 1 values for --axes 2" "a drift list shorter than the axes")
run(2 ${BIN}/dynblur_actuator_sim --axes 3 --plant ${dir}/pan_plant.yml --plant ${dir}/tilt_plant.yml --max-seconds 1)
expect("2 --plant files for --axes 3" "fewer plant files than axes")
run(2 ${BIN}/dynblur_actuator_sim --axes 9 --max-seconds 1)
expect("--axes = 9 must be in \\[1, 7\\]" "too many axes")

start_actuator_sim(${dir} bus ${BIN}/dynblur_actuator_sim --axes 3 --plant ${dir}/pan_plant.yml
                   --plant ${dir}/tilt_plant.yml --plant ${dir}/pan_plant.yml --drift-wn 0.03,-0.02,0
                   --csv ${dir}/theta.csv --log-tail 0.2 --max-seconds 30)

run(0 ${BIN}/dynblur_actuator_ctl --bus ${bus} --schedule ${dir}/pan.yml --schedule ${dir}/tilt.yml
    --schedule=${dir}/roll.yml --start --wait 2)
expect("protocol 1.1, max level 12.*axes 3" "the device's axes and the smallest plant file's max level")
expect("uploaded axis 2: 4 entries, verified" "the third axis verified")
# One START: every axis reports the same controller instant.
if(NOT last_output MATCHES "start axis 0: hostStartTime=[0-9.]+ [^\n]*controllerStartTime=([0-9.]+)")
  message(FATAL_ERROR "no start report of axis 0")
endif()
set(t0 ${CMAKE_MATCH_1})
if(NOT last_output MATCHES "start axis 2: hostStartTime=[0-9.]+ [^\n]*controllerStartTime=([0-9.]+)")
  message(FATAL_ERROR "no start report of axis 2")
endif()
if(NOT CMAKE_MATCH_1 STREQUAL t0)
  message(FATAL_ERROR "axes started at different controller instants: ${t0} and ${CMAKE_MATCH_1}")
endif()
expect("status axis 0: DONE, level 10.*status axis 1: DONE, level -5.*status axis 2: DONE, level 3"
       "every axis ran its own schedule")

# Two schedules for three axes: the host drives two, the third stays idle.
run(0 ${BIN}/dynblur_actuator_ctl --bus ${bus} --stop)
run(0 ${BIN}/dynblur_actuator_ctl --bus ${bus} --schedule ${dir}/pan.yml --schedule ${dir}/tilt.yml --status)
expect("status axis 0: LOADED.*status axis 1: LOADED" "two axes loaded")
# Four schedules for three axes; a bad one on axis 1 (nothing starts); both ways of naming one.
run(1 ${BIN}/dynblur_actuator_ctl --bus ${bus} --schedule ${dir}/pan.yml --schedule ${dir}/tilt.yml
    --schedule ${dir}/roll.yml --schedule ${dir}/roll.yml --start)
expect("has 3 axes, the host asks for 4" "more schedules than axes")
run(1 ${BIN}/dynblur_actuator_ctl --bus ${bus} --schedule ${dir}/pan.yml --schedule ${dir}/bad.yml --start)
expect("axis 1: schedule refused: levels\\[1\\] = 30 exceeds device max level = ±12" "a bad schedule on axis 1")
run(0 ${BIN}/dynblur_actuator_ctl --bus ${bus} --schedule ${dir}/pan.yml --status)
expect("status axis 0: (IDLE|DONE|LOADED)" "the status after the refusal")
if(last_output MATCHES "RUNNING")
  message(FATAL_ERROR "an axis runs after a refused upload")
endif()
run(2 ${BIN}/dynblur_actuator_ctl --bus ${bus} --upload ${dir}/pan.yml --schedule ${dir}/tilt.yml)
expect("--upload \\(one axis\\) and --schedule \\(one per axis\\) exclude each other" "--upload with --schedule")

stop_actuator_sim(${dir})
file(STRINGS ${dir}/theta.csv header LIMIT_COUNT 1)
if(NOT header STREQUAL "t,theta0,level0,theta1,level1,theta2,level2")
  message(FATAL_ERROR "the simulator's log of three axes has the header '${header}'")
endif()
