# SPDX-License-Identifier: Apache-2.0
# CTest script: a pan-tilt recording end to end with the programs: rendered (diagonal saccades of
# samples/data/pan_tilt.yml, a drifted truth), its timing calibrated (the clock, the line delay and
# each axis's plant), restored against its truth; and the refusals of a command log whose axes are not
# the mount's, a mount file with a plant missing.
# -DTOOL=dynblur_calibrate_timing -DRESTORE=dynblur_restore_video -DMOUNT=samples/data/pan_tilt.yml
# -DWORK=scratch folder
set(dir ${WORK}/mount_recording)
file(REMOVE_RECURSE ${dir})
file(MAKE_DIRECTORY ${dir})

include(${CMAKE_CURRENT_LIST_DIR}/cli_test_run.cmake)

run(0 ${TOOL} --simulate ${dir}/rec --mount ${MOUNT} --to 10,6 --saccades 2)
expect_written(${dir}/rec "the simulation" frames.csv commands.csv camera.xml mount.yml truth/scene.png truth/truth.yml)
file(STRINGS ${dir}/rec/commands.csv header REGEX "^t,")
if(NOT header STREQUAL "t,level0,level1")
  message(FATAL_ERROR "the mount's command log header is '${header}', not t,level0,level1")
endif()

run(0 ${TOOL} --recording ${dir}/rec --refine all --no-png)
expect("axis 1 natural frequency x" "the tilt's calibrated scale")
expect_written(${dir}/rec "the calibration" timing.yml)

run(0 ${RESTORE} --recording ${dir}/rec --truth ${dir}/rec/truth --out ${dir}/restored.avi)
expect("truth: gain over the recording, mean [+]" "a mean gain over the recording")

# Refusals, each naming the file and the option.
file(WRITE ${dir}/one_axis.csv "t,level\n0,0\n0.5,10\n")
run(1 ${TOOL} --recording ${dir}/rec --commands ${dir}/one_axis.csv --out ${dir}/bad.yml)
expect("one_axis.csv: the command log has 1 level column.*--mount" "a one-axis log for a mount")
if(EXISTS ${dir}/bad.yml)
  message(FATAL_ERROR "a timing file was written for a refused recording")
endif()
file(WRITE ${dir}/no_plant.yml "%YAML:1.0\n---\naxisCount: 2\naxis0: [0., 1., 0.]\naxis0_naturalFreqHz: 14.4\naxis0_dampingRatio: 0.12\naxis0_gain: 0.01745\naxis0_levels: [-16, 16]\naxis1: [1., 0., 0.]\naxis1_levels: [-16, 16]\n")
run(1 ${RESTORE} --recording ${dir}/rec --mount ${dir}/no_plant.yml --out ${dir}/bad.avi)
expect("no_plant.yml.*axis1_naturalFreqHz" "the mount file's missing plant")
