# SPDX-License-Identifier: Apache-2.0
# CTest script: the rehearsal of docs/your-rig.md, run as the document writes it (the block between
# its <!-- rehearsal --> markers, in order, under bash -e), on the simulated rig: the actuator
# simulator, a virtual camera, the chessboard views of the test data. Then checks what each step
# wrote.
# -DBIN=build/samples -DCALIB=build/calib -DDATA=test data -DDOC=docs/your-rig.md -DWORK=scratch folder
include(${CMAKE_CURRENT_LIST_DIR}/cli_test_run.cmake)
require_test_data(left01.jpg)
file(REMOVE_RECURSE ${WORK})
file(MAKE_DIRECTORY ${WORK})

run_rehearsal(${DOC})
expect_written(${WORK} "the rehearsal" rig/camera.xml rig/step.yml rig/response.csv rig/plant.yml rec/frames.csv
               rec/commands.csv rec/camera.xml rec/plant.yml rec/timing.yml restored.avi restored.csv)
# Every moving frame of the recording was restored or refused with a reason; the timing was found.
file(STRINGS ${WORK}/restored.csv rows REGEX "^[0-9]+,(I|II|III)")
list(LENGTH rows moving)
file(STRINGS ${WORK}/restored.csv restored REGEX "^[0-9]+,(I|II|III),1,")
list(LENGTH restored count)
message(STATUS "rehearsal: ${count} of ${moving} moving frames restored")
if(moving EQUAL 0 OR count EQUAL 0)
  message(FATAL_ERROR "no moving frame was restored")
endif()
