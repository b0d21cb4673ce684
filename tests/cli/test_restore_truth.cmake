# SPDX-License-Identifier: Apache-2.0
# CTest script: the shipped recording restored against its truth (samples/data/saccades/truth, the
# sharp scene it was rendered from): no moving frame ends below the recording by more than 0.1 dB,
# the most blurred frame gains at least 4.6 dB, and every moving frame is labelled with its window
# (docs/quality.md, "The shipped recording against its truth").
# -DBIN=build/samples -DREC=samples/data/saccades -DWORK=scratch folder
cmake_policy(SET CMP0007 NEW)  # empty CSV fields keep their place
set(dir ${WORK}/restore_truth)
file(REMOVE_RECURSE ${dir})
file(MAKE_DIRECTORY ${dir})
include(${CMAKE_CURRENT_LIST_DIR}/cli_test_run.cmake)

run(0 ${BIN}/dynblur_restore_video --recording ${REC} --truth ${REC}/truth --out ${dir}/restored.avi)
if(NOT last_output MATCHES "truth: gain over the recording, mean [-+][0-9.]+ dB")
  message(FATAL_ERROR "no truth summary line")
endif()
expect_written(${dir} "dynblur_restore_video (the contact sheet)" restored_frames.png)

# Columns: frame, window, restored, ..., reason (9th), window_as_told, blur_px, window_true,
# psnr_recorded_db, psnr_restored_db, gain_db.
file(READ ${dir}/restored.csv content)
string(REPLACE ";" " " content "${content}")  # the reason text writes its commas as ;
string(REGEX REPLACE "\n$" "" content "${content}")
string(REPLACE "\n" ";" rows "${content}")
list(REMOVE_AT rows 0)
set(moving 0)
set(mostBlur -1)
foreach(row IN LISTS rows)
  string(REPLACE "," ";" fields "${row}")
  list(GET fields 0 frame)
  list(GET fields 1 window)
  if(window STREQUAL "still")
    continue()
  endif()
  math(EXPR moving "${moving} + 1")
  list(GET fields 10 blur)
  list(GET fields 11 trueWindow)
  list(GET fields 14 gain)
  if(NOT window MATCHES "^(I|II|III|IV)$" OR NOT trueWindow MATCHES "^(I|II|III|IV)$")
    message(FATAL_ERROR "frame ${frame}: windows '${window}', '${trueWindow}'")
  endif()
  if(gain LESS -0.1)
    message(FATAL_ERROR "frame ${frame} ends ${gain} dB below the recording (at most 0.1 dB allowed)")
  endif()
  if(blur GREATER mostBlur)
    set(mostBlur ${blur})
    set(mostBlurred ${frame})
    set(mostBlurredGain ${gain})
  endif()
endforeach()
if(moving LESS 5)
  message(FATAL_ERROR "${moving} moving frames; the recording has 6")
endif()
if(mostBlurredGain LESS 4.6)
  message(FATAL_ERROR "the most blurred frame ${mostBlurred} (${mostBlur} px) gains ${mostBlurredGain} dB, under 4.6 dB")
endif()
message(STATUS "most blurred frame ${mostBlurred} (${mostBlur} px): ${mostBlurredGain} dB")
