# SPDX-License-Identifier: Apache-2.0
# CTest script: render a hand-held recording with its gyro log (5 ms ahead of the camera, line delay
# 3 % longer than the frame log says, 0.5 deg/s bias), calibrate it with dynblur_calibrate_timing
# --gyro, check the timing file and the plot, restore it with dynblur_restore_video --gyro; and both
# programs' refusals of bad gyro options and logs, each naming the option.
# -DTOOL=dynblur_calibrate_timing -DRESTORE=dynblur_restore_video -DWORK=scratch folder
set(dir ${WORK}/gyro)
file(REMOVE_RECURSE ${dir})
file(MAKE_DIRECTORY ${dir})

include(${CMAKE_CURRENT_LIST_DIR}/cli_test_run.cmake)

run(0 ${TOOL} --help)
if(NOT last_output MATCHES "--gyro LOG" OR NOT last_output MATCHES "--simulate-gyro DIR")
  message(FATAL_ERROR "--help does not describe the gyro path")
endif()
run(0 ${TOOL} --simulate-gyro ${dir}/rec)
set(rec --gyro ${dir}/rec/gyro.gcsv --video ${dir}/rec/frame_%04d.png --frames ${dir}/rec/frames.csv
        --camera ${dir}/rec/camera.xml)
run(0 ${TOOL} ${rec} --out ${dir}/timing.yml)
read_timing_file(${dir})
message(STATUS "timing file: timeOffset=${timeOffset} lineDelayScale=${lineDelayScale}")
# The file writes 5.03...e-03: the offset in [4.5, 5.5) ms, the line delay scale in [1.0, 1.06).
if(NOT timeOffset MATCHES "^(4\\.[5-9]|5\\.[0-4])[0-9]*e-03$")
  message(FATAL_ERROR "timeOffset ${timeOffset} is not within 0.5 ms of the 5 ms simulated")
endif()
if(NOT lineDelayScale MATCHES "^1\\.0[0-5]")
  message(FATAL_ERROR "lineDelayScale ${lineDelayScale} is not within [1.00, 1.06) (1.03 simulated)")
endif()
if(NOT last_output MATCHES "gyro bias +\\(\\+0\\.[45][0-9]*, -0\\.[45][0-9]*, \\+0\\.[45]")
  message(FATAL_ERROR "the bias printed is not within 0.1 deg/s of (0.5, -0.5, 0.5)")
endif()

run(0 ${RESTORE} ${rec} --timing ${dir}/timing.yml --out ${dir}/restored.avi)
expect_written(${dir} dynblur_restore_video restored.avi restored.csv)
file(STRINGS ${dir}/restored.csv rows REGEX ",II,1,")
list(LENGTH rows restoredRows)
if(restoredRows LESS 10)
  message(FATAL_ERROR "only ${restoredRows} frames moving throughout were restored")
endif()

# Refusals: usage errors exit 2 naming the option; a bad log or recording exits 1 naming the file.
run(2 ${TOOL} ${rec} --gyro-bias 1,2 --out ${dir}/bad.yml)
if(NOT last_output MATCHES "--gyro-bias")
  message(FATAL_ERROR "a bad --gyro-bias is not named")
endif()
run(2 ${TOOL} ${rec} --refine offset,plant --out ${dir}/bad.yml)
if(NOT last_output MATCHES "--refine takes offset, line-delay and bias")
  message(FATAL_ERROR "--refine plant with --gyro is not refused by name")
endif()
run(1 ${RESTORE} --gyro ${dir}/rec/gyro.gcsv --video ${dir}/rec/frame_%04d.png --exposure 0.008 --readout 0.02)
if(NOT last_output MATCHES "--video: .*frame_%04d.png' is an image sequence, which has no frame timestamps.*--frames")
  message(FATAL_ERROR "an image sequence without --frames is not refused by name")
endif()
file(WRITE ${dir}/unsorted.gcsv "GYROFLOW IMU LOG\nversion,1.3\norientation,XYZ\ntscale,0.001\ngscale,1\nt,gx,gy,gz\n0,0,0,0\n5,0,0,0\n4,0,0,0\n")
run(1 ${RESTORE} ${rec} --gyro ${dir}/unsorted.gcsv --out ${dir}/bad.avi)
if(NOT last_output MATCHES "--gyro: .*unsorted.gcsv.*increas")
  message(FATAL_ERROR "an unsorted gyro log is not named")
endif()
file(WRITE ${dir}/short.gcsv "GYROFLOW IMU LOG\nversion,1.3\norientation,XYZ\ntscale,0.001\ngscale,1\nt,gx,gy,gz\n0,0,0,0\n5,0,0,0\n10,0,0,0\n")
run(1 ${TOOL} ${rec} --gyro ${dir}/short.gcsv --out ${dir}/bad.yml)
if(NOT last_output MATCHES "--gyro: '[^']*short.gcsv' covers no frame of --video at any clock offset")
  message(FATAL_ERROR "a log that covers no frame is not named")
endif()
foreach(f bad.yml bad.avi)
  if(EXISTS ${dir}/${f})
    message(FATAL_ERROR "${f} was written although the input was refused")
  endif()
endforeach()
