# SPDX-License-Identifier: Apache-2.0
# dynblur_visual_servo --mount: a short pan-tilt run writes its outputs with both axes' levels, and the
# program refuses a mount of one axis, a place the mount cannot reach (naming the axis and its range),
# a circle without a mount and a missing mount file, each with exit code 2 and a message.
include(${CMAKE_CURRENT_LIST_DIR}/cli_test_run.cmake)
set(work ${WORK}/visual_servo_mount)
file(REMOVE_RECURSE ${work})
file(MAKE_DIRECTORY ${work})

run(0 ${TOOL} --mount pan-tilt --cycles 3 --frames-per-cycle 2 --iterations 10 --out ${work}/step)
expect("error <= 1 px from cycle [0-2] on" "a pan-tilt step")
expect_written(${work}/step "dynblur_visual_servo --mount pan-tilt" cycles.csv frames.csv error.png detection.png)
file(STRINGS ${work}/step/cycles.csv header LIMIT_COUNT 1)
if(NOT header MATCHES "from_pan_level,from_tilt_level")
  message(FATAL_ERROR "cycles.csv has no level of each axis: ${header}")
endif()

file(WRITE ${work}/tilt_only.yml "%YAML:1.0\n---\naxisCount: 1\naxis0: [ 1., 0., 0. ]\naxis0_naturalFreqHz: 14.4\n"
     "axis0_dampingRatio: 0.12\naxis0_gain: 8.7266462599716477e-04\naxis0_levels: [ -400, 400 ]\n")
run(2 ${TOOL} --mount ${work}/tilt_only.yml --out ${work}/refused)
expect("two axes or more" "a mount of one axis")
run(2 ${TOOL} --mount pan-tilt --start-deg 30 --out ${work}/refused)
expect("axis 0 must turn to 21.21 deg to centre it, beyond its range \\[-20.00, 20.00\\] deg" "a place out of reach")
run(2 ${TOOL} --mount ${MOUNT} --start-deg 30 --out ${work}/refused)
expect("axis 0 must turn to 21.21 deg.*\\[-16.00, 16.00\\] deg" "a place beyond a mount file's range")
run(2 ${TOOL} --scenario circle --out ${work}/refused)
expect("--scenario circle needs --mount" "a circle on one axis")
run(2 ${TOOL} --mount ${work}/missing.yml --out ${work}/refused)
expect("cannot open the mount file" "a missing mount file")
if(EXISTS ${work}/refused)
  message(FATAL_ERROR "a refused run wrote ${work}/refused")
endif()
