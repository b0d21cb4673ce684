# SPDX-License-Identifier: Apache-2.0
# CTest script: dynblur_simulate_clip writes a small hand-held clip as a phone would (mp4, Sensor
# Logger's Gyroscope.csv in the phone's axes, the log's clock 1.5 s behind) and as an image sequence
# with a plain CSV log and the truth views; its truth file states what was asked; bad options are
# refused by name, exit 2 (exit 1 for a scene that cannot be read), and leave no file.
# -DTOOL=dynblur_simulate_clip -DWORK=scratch folder
set(dir ${WORK}/simulate_clip)
file(REMOVE_RECURSE ${dir})
file(MAKE_DIRECTORY ${dir})

include(${CMAKE_CURRENT_LIST_DIR}/cli_test_run.cmake)

run(0 ${TOOL} --help)
if(NOT last_output MATCHES "--gyro-format NAME" OR NOT last_output MATCHES "--max-blur PX")
  message(FATAL_ERROR "--help does not list the options")
endif()
set(small --size 96x64 --focal 90 --frames 6 --max-blur 5)

run(0 ${TOOL} ${small} --out ${dir}/phone --video clip.mp4 --gyro-format sensor-logger --gyro-axes Xyz
    --offset -1.5 --gyro-bias 0.5,-0.5,1 --still 0.05 --shaky 0.15)
expect_written(${dir}/phone dynblur_simulate_clip clip.mp4 Gyroscope.csv camera.xml frames.csv truth.yml)
if(NOT last_output MATCHES "blur [0-9.]+ to 5.00 px per frame")
  message(FATAL_ERROR "the largest blur reported is not the 5 px asked")
endif()
file(STRINGS ${dir}/phone/Gyroscope.csv header LIMIT_COUNT 1)
if(NOT header STREQUAL "time,seconds_elapsed,z,y,x")
  message(FATAL_ERROR "Gyroscope.csv starts with '${header}'")
endif()
read_yaml_numbers(${dir}/phone/truth.yml)
if(NOT timeOffset EQUAL -1.5 OR NOT frameCount EQUAL 6)
  message(FATAL_ERROR "truth.yml states timeOffset ${timeOffset} and frameCount ${frameCount}")
endif()
file(READ ${dir}/phone/truth.yml truth)
if(NOT truth MATCHES "gyroAxes: Xyz" OR NOT truth MATCHES "gyroFormat: sensor-logger" OR NOT truth MATCHES "still:1")
  message(FATAL_ERROR "truth.yml does not state the axes, the format and the still frames")
endif()

run(0 ${TOOL} ${small} --out ${dir}/sequence --video frame_%04d.png --gyro-format csv --gyro-units s,rad/s
    --readout 0 --truth-frames truth_%04d.png)
expect_written(${dir}/sequence dynblur_simulate_clip frame_0000.png frame_0005.png truth_0005.png gyro.csv truth.yml)
file(STRINGS ${dir}/sequence/gyro.csv header LIMIT_COUNT 2)
if(NOT header MATCHES "units of 1 s.*units of 1 rad/s.*;t,gx,gy,gz$")
  message(FATAL_ERROR "gyro.csv starts with '${header}'")
endif()

# Refusals name the option; nothing is written.
foreach(bad "--exposure;10;--exposure" "--gyro-axes;XYz;--gyro-axes" "--size;1920;--size" "--gyro-units;ms,rpm;--gyro-units"
            "--video;clip.mkv;--video" "--band;20,1;--band" "--gyro-bias;50,0,0;--gyro-bias" "--frames;0;--frames")
  list(GET bad 0 option)
  list(GET bad 1 value)
  list(GET bad 2 named)
  run(2 ${TOOL} ${small} --out ${dir}/refused ${option} ${value})
  if(NOT last_output MATCHES "error: ${named}")
    message(FATAL_ERROR "${option} ${value} is refused without naming ${named}")
  endif()
endforeach()
run(2 ${TOOL} ${small} --out ${dir}/refused --peak-rate 10)
if(NOT last_output MATCHES "--peak-rate and --max-blur")
  message(FATAL_ERROR "--peak-rate with --max-blur is not refused by name")
endif()
run(1 ${TOOL} ${small} --out ${dir}/refused --image ${dir}/missing.png)
if(NOT last_output MATCHES "error: --image: .*missing.png")
  message(FATAL_ERROR "a missing --image is not named")
endif()
if(EXISTS ${dir}/refused)
  message(FATAL_ERROR "a refused command line wrote ${dir}/refused")
endif()
