# CTest script: simulate a recording whose clock runs late, calibrate its timing with the CLI, check
# the exit codes, the timing file and the plot; and the CLI's refusals of bad logs and videos.
# -DTOOL=dynblur_calibrate_timing -DWORK=scratch folder
set(dir ${WORK}/timing)
file(REMOVE_RECURSE ${dir})
file(MAKE_DIRECTORY ${dir})

include(${CMAKE_CURRENT_LIST_DIR}/cli_test_run.cmake)

# Two saccades, the camera's clock 1.5 ms late; only the offset is estimated.
run(0 ${TOOL} --simulate ${dir}/rec --saccades 2 --true-offset 0.0015 --true-line-delay-scale 1
    --true-hz-scale 1 --true-zeta-scale 1)
set(rec --video ${dir}/rec/frame_%04d.png --frames ${dir}/rec/frames.csv --commands ${dir}/rec/commands.csv
        --camera ${dir}/rec/camera.xml --plant ${dir}/rec/plant.yml)
run(0 ${TOOL} ${rec} --refine offset --out ${dir}/timing.yml)
foreach(f timing.yml timing_objective.png)
  if(NOT EXISTS ${dir}/${f})
    message(FATAL_ERROR "${f} was not written")
  endif()
endforeach()
file(STRINGS ${dir}/timing.yml lines)
foreach(line ${lines})
  if(line MATCHES "^([a-zA-Z]+): *([-+0-9.eE]+)$")
    set(${CMAKE_MATCH_1} ${CMAKE_MATCH_2})
  endif()
endforeach()
message(STATUS "timing file: timeOffset=${timeOffset} lineDelayScale=${lineDelayScale}")
# CMake compares decimals only, and the file writes 1.49...e-03: the offset in [1.4, 1.6) ms.
if(NOT timeOffset MATCHES "^1\\.[45][0-9]*e-03$")
  message(FATAL_ERROR "timeOffset ${timeOffset} is not within [1.4, 1.6) ms of the 1.5 ms simulated")
endif()
if(NOT lineDelayScale EQUAL 1)
  message(FATAL_ERROR "lineDelayScale ${lineDelayScale} changed although only the offset was refined")
endif()

# Refusals: a usage error exits 2; a bad recording exits 1 with a message naming what is wrong;
# no timing file is left behind.
run(2 ${TOOL} --frames ${dir}/rec/frames.csv)
if(NOT last_output MATCHES "--video is required")
  message(FATAL_ERROR "missing --video not named")
endif()
run(2 ${TOOL} ${rec} --refine offset,speed)
file(WRITE ${dir}/unsorted.csv "t,level\n0.0,0\n0.5,6\n0.4,10\n")
run(1 ${TOOL} ${rec} --commands ${dir}/unsorted.csv --out ${dir}/bad.yml)
if(NOT last_output MATCHES "unsorted.csv:4: 't' must increase")
  message(FATAL_ERROR "the unsorted command log is not named with its line")
endif()
file(WRITE ${dir}/nostart.csv "frame,exposure,line_delay\n0,0.008,6.9e-05\n")
run(1 ${TOOL} ${rec} --frames ${dir}/nostart.csv --out ${dir}/bad.yml)
if(NOT last_output MATCHES "no column 'frame_start'")
  message(FATAL_ERROR "the missing frame_start column is not named")
endif()
file(WRITE ${dir}/beyond.csv "frame,frame_start,exposure,line_delay\n0,0.0,0.008,6.9e-05\n5000,0.1,0.008,6.9e-05\n")
run(1 ${TOOL} ${rec} --frames ${dir}/beyond.csv --out ${dir}/bad.yml)
if(NOT last_output MATCHES "frame 5000, but the video ends after")
  message(FATAL_ERROR "a frame beyond the video is not named")
endif()
run(1 ${TOOL} ${rec} --video ${dir}/missing.avi --out ${dir}/bad.yml)
if(NOT last_output MATCHES "cannot open")
  message(FATAL_ERROR "a video that cannot be opened is not named")
endif()
if(EXISTS ${dir}/bad.yml)
  message(FATAL_ERROR "a refused calibration left a timing file behind")
endif()
