# SPDX-License-Identifier: Apache-2.0
# CTest script: the rehearsal of docs/hand-held.md, run as the document writes it (run_rehearsal): a
# rendered clip as a phone writes it (clip.mp4, Sensor Logger's Gyroscope.csv on a clock 1.3 s ahead,
# no frame log, no still frame, the readout untold), calibrated and restored by the document's two
# commands. Checks the calibration against the truth (offset within 1 ms, readout within 3 %, bias
# within 0.1 deg/s), the restored video (the input's frame count, size and rate) and its CSV (a row per
# frame, the positioner mode's columns). Then the refusals of bad input on the same clip, each naming
# the file and the option; a restoration that fails midway keeps the frames it wrote; a log the frames
# contradict leaves every frame as recorded, with the reason.
# -DBIN=build/samples -DCALIB=build/calib -DINFO=dynblur_video_info -DDOC=docs/hand-held.md -DWORK=scratch
include(${CMAKE_CURRENT_LIST_DIR}/cli_test_run.cmake)
file(REMOVE_RECURSE ${WORK})
file(MAKE_DIRECTORY ${WORK})
set(CALIBRATE ${CALIB}/dynblur_calibrate_timing)
set(RESTORE ${BIN}/dynblur_restore_video)

# to_milli(TEXT VAR): VAR = TEXT (a decimal such as "+0.501" or "19.880") times 1000, an integer.
function(to_milli text var)
  if(NOT text MATCHES "^([-+]?)([0-9]+)\\.([0-9][0-9][0-9])")
    message(FATAL_ERROR "'${text}' is not a number with three decimals")
  endif()
  math(EXPR value "${CMAKE_MATCH_2} * 1000 + 1${CMAKE_MATCH_3} - 1000")
  if(CMAKE_MATCH_1 STREQUAL "-")
    math(EXPR value "-${value}")
  endif()
  set(${var} ${value} PARENT_SCOPE)
endfunction()

# expect_within(WHAT VALUE TRUTH TOLERANCE): fails unless |VALUE - TRUTH| <= TOLERANCE (integers).
function(expect_within what value truth tolerance)
  math(EXPR error "${value} - (${truth})")
  message(STATUS "${what}: ${value} against ${truth} (error ${error}, allowed ${tolerance})")
  if(error GREATER tolerance OR error LESS -${tolerance})
    message(FATAL_ERROR "${what} is off by ${error}, more than ${tolerance}")
  endif()
endfunction()

string(TIMESTAMP begin "%s")
run_rehearsal(${DOC})
string(TIMESTAMP end "%s")
math(EXPR seconds "${end} - ${begin}")
message(STATUS "the rehearsal took ${seconds} s")
set(rehearsal "${last_output}")
set(dir ${WORK}/phone)
expect_written(${dir} "the rehearsal" clip.mp4 Gyroscope.csv camera.xml truth.yml timing.yml timing_objective.png
               restored.mp4 restored.csv restored_frames.png)

# The calibration against the truth the clip was rendered with.
read_yaml_numbers(${dir}/truth.yml)
set(trueOffset ${timeOffset})
set(trueReadout ${readoutTime})
read_yaml_numbers(${dir}/timing.yml)
if(NOT trueOffset EQUAL 1.3 OR NOT trueReadout MATCHES "^2\\.0+e-02$")
  message(FATAL_ERROR "the clip was rendered with the offset ${trueOffset} s and the readout ${trueReadout} s, not "
                      "the 1.3 s and 20 ms of docs/hand-held.md")
endif()
# timeOffset is written as 1.30002e+00: microseconds from its first seven digits.
if(NOT timeOffset MATCHES "^1\\.([0-9][0-9][0-9][0-9][0-9][0-9])[0-9]*e\\+00$")
  message(FATAL_ERROR "timeOffset ${timeOffset} is not within 1 s of the 1.3 s simulated")
endif()
math(EXPR offsetUs "1${CMAKE_MATCH_1}")
expect_within("clock offset, us" ${offsetUs} 1300000 1000)
if(NOT rehearsal MATCHES "readout ([0-9]+\\.[0-9]+) ms \\(x")
  message(FATAL_ERROR "dynblur_calibrate_timing printed no readout")
endif()
to_milli(${CMAKE_MATCH_1} readoutUs)
expect_within("readout, us" ${readoutUs} 20000 600)
if(NOT rehearsal MATCHES "gyro bias +\\(([-+][0-9.]+), ([-+][0-9.]+), ([-+][0-9.]+)\\) deg/s")
  message(FATAL_ERROR "dynblur_calibrate_timing printed no gyro bias")
endif()
set(biases ${CMAKE_MATCH_1} ${CMAKE_MATCH_2} ${CMAKE_MATCH_3})
set(truths 500 -300 200)
foreach(axis 0 1 2)
  list(GET biases ${axis} text)
  list(GET truths ${axis} truth)
  to_milli(${text} bias)
  expect_within("gyro bias ${axis}, mdeg/s" ${bias} ${truth} 100)
endforeach()

# The restored video: the input's frame count, size and rate.
run(0 ${INFO} ${dir}/clip.mp4)
string(REGEX MATCH "frames [0-9]+ size [0-9]+x[0-9]+ fps [0-9.]+" input "${last_output}")
run(0 ${INFO} ${dir}/restored.mp4)
string(REGEX MATCH "frames [0-9]+ size [0-9]+x[0-9]+ fps [0-9.]+" output "${last_output}")
if(NOT input MATCHES "^frames 75 size 640x480 fps 30$" OR NOT output STREQUAL input)
  message(FATAL_ERROR "the restored video is '${output}', the input '${input}'")
endif()
# Its CSV: a row per frame, with the positioner mode's columns first. (Read whole and matched: a reason
# holds ';', which a CMake list would split on.)
file(READ ${dir}/restored.csv text)
string(CONCAT columns "^frame,window,restored,time_offset_s,line_delay_scale,natural_freq_scale,damping_scale,"
       "consistency,reason,window_as_told,blur_px,window_true,psnr_recorded_db,psnr_restored_db,gain_db,")
if(NOT text MATCHES "${columns}")
  message(FATAL_ERROR "restored.csv does not start with the columns ${columns}")
endif()
string(REGEX MATCHALL "\n[0-9]+,(I|II|III|still),[01]," rows "${text}")
list(LENGTH rows rows)
string(REGEX MATCHALL "\n[0-9]+,I+,1," restored "${text}")
list(LENGTH restored restored)
message(STATUS "restored.csv: ${rows} rows, ${restored} frames restored")
if(NOT rows EQUAL 75 OR restored LESS 60)
  message(FATAL_ERROR "restored.csv has ${rows} frame rows (75 expected), ${restored} restored")
endif()
if(NOT rehearsal MATCHES "75 frame\\(s\\): [0-9]+ restored, [0-9]+ skipped \\(still or sharp\\), [0-9]+ refused")
  message(FATAL_ERROR "dynblur_restore_video printed no summary line")
endif()

# Refusals: each names the file and the option, exit 1 (2 for bad usage), and writes nothing.
set(clip --video ${dir}/clip.mp4 --camera ${dir}/camera.xml --exposure 0.01)
set(gyro --gyro ${dir}/Gyroscope.csv)
# expect_refused(EXIT PATTERN args...): the calibration exits EXIT with a message matching PATTERN.
function(expect_refused code pattern)
  run(${code} ${CALIBRATE} ${ARGN} --out ${WORK}/bad.yml)
  if(NOT last_output MATCHES "${pattern}")
    message(FATAL_ERROR "the refusal does not match '${pattern}'")
  endif()
endfunction()
file(WRITE ${WORK}/garbage.mp4 "not a video\n")
expect_refused(1 "error: --video: '[^']*missing.mp4' does not exist" ${gyro} --video ${WORK}/missing.mp4
               --camera ${dir}/camera.xml --exposure 0.01)
expect_refused(1 "error: --video: cannot open '[^']*garbage.mp4'" ${gyro} --video ${WORK}/garbage.mp4
               --camera ${dir}/camera.xml --exposure 0.01)
expect_refused(1 "error: --video: '[^']*frame_%04d.png' is an image sequence, which has no frame timestamps.*--frames"
               ${gyro} --video ${WORK}/frame_%04d.png --camera ${dir}/camera.xml --exposure 0.01)
expect_refused(1 "error: --exposure: the exposure 0.05 s is longer than the frame period 0.0333333 s of '[^']*clip.mp4'"
               ${gyro} --video ${dir}/clip.mp4 --camera ${dir}/camera.xml --exposure 0.05)
expect_refused(2 "error: --exposure: the exposure of a frame is not known" ${gyro} --video ${dir}/clip.mp4
               --camera ${dir}/camera.xml)
expect_refused(1 "error: --gyro: '[^']*Gyroscope.csv' covers no frame of --video at any clock offset within \\+-2 s \\(--max-offset\\)"
               ${gyro} --gyro-time-origin 1699999900 ${clip})

# Broken logs, made from the clip's: shorter than the clip, with a gap, with a repeated sample, without a column.
file(STRINGS ${dir}/Gyroscope.csv samples)
list(SUBLIST samples 0 300 lines)
string(REPLACE ";" "\n" text "${lines}")
file(WRITE ${WORK}/short.csv "${text}\n")
set(lines ${samples})
list(REMOVE_AT lines 100 101 102 103 104 105 106 107 108 109)
string(REPLACE ";" "\n" text "${lines}")
file(WRITE ${WORK}/gap.csv "${text}\n")
set(lines ${samples})
list(GET lines 100 repeated)
list(INSERT lines 100 "${repeated}")
string(REPLACE ";" "\n" text "${lines}")
file(WRITE ${WORK}/repeat.csv "${text}\n")
string(REGEX REPLACE ",[^,;]*(;|$)" "\\1" lines "${samples}")
string(REPLACE ";" "\n" text "${lines}")
file(WRITE ${WORK}/nox.csv "${text}\n")
expect_refused(1 "error: --gyro: '[^']*short.csv' does not cover the stretch calibrated.*--clip-from, --clip-seconds"
               --gyro ${WORK}/short.csv ${clip})
expect_refused(1 "error: --gyro: [^\n]*gap.csv:101: a gap of 0.055 s" --gyro ${WORK}/gap.csv ${clip})
expect_refused(1 "error: --gyro: [^\n]*repeat.csv:102: field 'time'.*not after the previous sample.*--gyro-drop-repeats"
               --gyro ${WORK}/repeat.csv ${clip})
expect_refused(1 "error: --gyro: [^\n]*nox.csv:1: .*no known layout.*--gyro-columns" --gyro ${WORK}/nox.csv ${clip})
expect_refused(1 "error: --gyro: [^\n]*Gyroscope.csv:1: --gyro-columns: no column 'w'" ${gyro} --gyro-columns time,x,y,w ${clip})
if(EXISTS ${WORK}/bad.yml)
  message(FATAL_ERROR "a refused calibration wrote bad.yml")
endif()

# The restorer: the shutter must be told; a log shorter than the clip fails at its end, keeping the frames before.
set(restore ${RESTORE} ${gyro} --video ${dir}/clip.mp4 --camera ${dir}/camera.xml --out ${WORK}/bad.mp4)
run(2 ${restore})
if(NOT last_output MATCHES "error: --exposure: the exposure of a frame is not known")
  message(FATAL_ERROR "a missing --exposure is not named")
endif()
run(2 ${restore} --exposure 0.01)
if(NOT last_output MATCHES "error: --readout: the line delay is not known")
  message(FATAL_ERROR "a missing --readout is not named")
endif()
run(1 ${RESTORE} --gyro ${WORK}/short.csv --video ${dir}/clip.mp4 --camera ${dir}/camera.xml
    --timing ${dir}/timing.yml --out ${WORK}/part.mp4)
if(NOT last_output MATCHES "error: --gyro: frame ([0-9]+) [^\n]*outside the span of '[^']*short.csv'")
  message(FATAL_ERROR "a log shorter than the clip is not named")
endif()
set(failed ${CMAKE_MATCH_1})
if(NOT last_output MATCHES "the ${failed} frame\\(s\\) written before it are kept, closed: [^\n]*part.mp4 and [^\n]*part.csv")
  message(FATAL_ERROR "the frames written before the failure are not reported as kept")
endif()
run(0 ${INFO} ${WORK}/part.mp4)
file(READ ${WORK}/part.csv text)
string(REGEX MATCHALL "\n[0-9]+," partRows "${text}")
list(LENGTH partRows partCount)
if(failed LESS 1 OR NOT last_output MATCHES "^frames ${failed} size 640x480 fps 30 " OR NOT partCount EQUAL failed)
  message(FATAL_ERROR "part.mp4 ('${last_output}') and part.csv (${partCount} rows) do not hold the ${failed} frames "
                      "written")
endif()
# A log the frames contradict (its axes mapped wrong after the calibration): each frame, checked against
# its neighbour, is written as recorded, the CSV saying why.
run(0 ${RESTORE} ${gyro} --gyro-orientation YXz --video ${dir}/clip.mp4 --camera ${dir}/camera.xml
    --timing ${dir}/timing.yml --out ${WORK}/wrong.mp4)
if(NOT last_output MATCHES "75 frame\\(s\\): 0 restored, 0 skipped \\(still or sharp\\), 75 refused \\(written as recorded\\)")
  message(FATAL_ERROR "the frames of a log with wrong axes are not all refused")
endif()
file(READ ${WORK}/wrong.csv text)
string(REGEX MATCHALL "\n[0-9]+,II,0," rows "${text}")
list(LENGTH rows rows)
string(REGEX MATCHALL "the log does not explain the frame" reasons "${text}")
list(LENGTH reasons reasons)
if(NOT rows EQUAL 75 OR NOT reasons EQUAL 75)
  message(FATAL_ERROR "wrong.csv has ${rows} frames not restored, ${reasons} saying why, of 75")
endif()
if(EXISTS ${WORK}/bad.mp4 OR EXISTS ${WORK}/part_frames.png)
  message(FATAL_ERROR "a refused restoration wrote bad.mp4, or the failed one its contact sheet")
endif()
