# SPDX-License-Identifier: Apache-2.0
# CTest script: the programs chain (dynblur_plan's schedule read by dynblur_actuator_ctl and the
# demo; dynblur_record's folder read by the restorer), take --name value and --name=value, and refuse
# each likely unit mistake with a message naming the option and the unit, at once (the test's
# timeout is the guard against a hang).
# -DBIN=build/samples -DCALIB=build/calib -DREC=samples/data/saccades -DWORK=scratch folder
set(dir ${WORK}/programs)
file(REMOVE_RECURSE ${dir})
file(MAKE_DIRECTORY ${dir})
include(${CMAKE_CURRENT_LIST_DIR}/cli_test_run.cmake)

# --- dynblur_plan: both spellings, the schedule file it writes, units in its CSV header.
run(0 ${BIN}/dynblur_plan --deg --from 0 --to 10 --out ${dir}/move)
run(0 ${BIN}/dynblur_plan --deg --from=0 --to=10 --mode=robust --out=${dir}/robust)
expect_written(${dir} dynblur_plan move.yml move.csv move.png robust.yml)
file(STRINGS ${dir}/move.csv header LIMIT_COUNT 1)
if(NOT header STREQUAL "t_s,theta_rad,omega_rad_per_s,level")
  message(FATAL_ERROR "plan CSV header without units: ${header}")
endif()
run(2 ${BIN}/dynblur_plan --to 10 --out ${dir}/bad)
expect("--to = 10 rad is outside the reachable range.*radians expected.*--deg reads degrees" "--to in degrees without --deg")
run(2 ${BIN}/dynblur_plan --deg --to 0.3 --out ${dir}/bad)
expect("rounds to zero levels of 1 deg each" "a move smaller than a level")
run(2 ${BIN}/dynblur_plan --deg --to 10 --gain-deg 57.3 --out ${dir}/bad)
expect("gain = 1.00007 rad per level.*implausible.*is it in degrees" "a gain of 57 degrees per level")
run(2 ${BIN}/dynblur_plan --deg --to 10 --hz 5000 --out ${dir}/bad)
expect("naturalFreqHz = 5000 Hz is implausible" "a natural frequency of 5 kHz")
run(2 ${BIN}/dynblur_plan --deg --to 10 --frobnicate 1)
expect("unknown option '--frobnicate'" "an unknown option")

# --- The schedule chains into the controller (the simulator) and the demo's real-frame mode.
start_actuator_sim(${dir} bus ${BIN}/dynblur_actuator_sim --csv= --max-seconds 20)
run(0 ${BIN}/dynblur_actuator_ctl --bus ${bus} --upload ${dir}/move.yml --start --wait 2)
expect("uploaded: [0-9]+ entries, verified" "the controller did not take the planned schedule")
# dynblur_record drives moves over the bus while a virtual camera plays; both logs on its clock.
run(0 ${BIN}/dynblur_record --source ${REC}/frames.avi --exposure 0.008 --line-delay 6.94444444e-05
    --camera ${REC}/camera.xml --plant ${REC}/plant.yml --bus ${bus} --moves 5,0 --still 0.3 --out ${dir}/driven)
expect("move 1 to 5 deg started at 0.3[0-9]* s.*move 2 to 0 deg started at" "the moves over the bus")
file(STRINGS ${dir}/driven/commands.csv switches REGEX "^[0-9]")
list(LENGTH switches count)
if(count LESS 3)
  message(FATAL_ERROR "dynblur_record logged ${count} commands for two moves")
endif()
stop_actuator_sim(${dir})

# --- dynblur_record: a virtual camera (the shipped video at its rate) and a script's command log,
# read back by the restorer.
run(0 ${BIN}/dynblur_record --source ${REC}/frames.avi --exposure 0.008 --line-delay 6.94444444e-05
    --camera ${REC}/camera.xml --plant ${REC}/plant.yml --commands ${REC}/commands.csv --frames 40 --out ${dir}/rec)
expect("virtual camera .* at 30 fps" "the virtual camera's rate")
expect("recorded 40 frames" "the frame count")
run(0 ${BIN}/dynblur_restore_video --recording ${dir}/rec --model rows --refine none --out ${dir}/rec_restored.avi)
file(STRINGS ${dir}/rec_restored.csv header LIMIT_COUNT 1)
if(NOT header MATCHES "time_offset_s")
  message(FATAL_ERROR "restore CSV header without units: ${header}")
endif()
run(2 ${BIN}/dynblur_record --source ${REC}/frames.avi --exposure 8 --line-delay 6.9e-05 --out ${dir}/bad)
expect("--exposure 8 must be in \\(0, 1\\] seconds" "dynblur_record's exposure in ms")
run(1 ${BIN}/dynblur_record --source ${dir}/nothing.avi --exposure 0.008 --line-delay 6.9e-05 --out ${dir}/bad)
expect("--source: the file '[^']*nothing.avi' does not exist" "a missing source")

# One recorded frame, restored with the planned schedule and a timing file.
file(WRITE ${dir}/timing.yml "%YAML:1.0\n---\ntimeOffset: 1.0e-03\nlineDelayScale: 1.0\nnaturalFreqScale: 1.0\ndampingScale: 1.0\n")
run(0 ${BIN}/dynblur_demo --frame ${dir}/rec/frame_0001.png --schedule ${dir}/move.yml --frame-start 0.01
    --camera ${REC}/camera.xml --plant ${REC}/plant.yml --timing ${dir}/timing.yml --model rows --iterations 2
    --out ${dir}/demo)
expect_written(${dir}/demo dynblur_demo restored.png)
run(2 ${BIN}/dynblur_demo --timing ${dir}/timing.yml)
expect("--timing belongs to the real-frame mode" "--timing without --frame")
run(1 ${BIN}/dynblur_demo --frame ${dir}/rec/frame_0001.png --schedule ${dir}/move.yml --frame-start 0.01
    --camera ${REC}/camera.xml --timing ${dir}/nope.yml --out ${dir}/demo)
expect("TimingCalibration::load: cannot open the timing file '[^']*nope.yml'" "a missing timing file")
expect("note: no --plant: using the seed's plant" "the default plant is not announced")

# --- dynblur_restore_video: unit mistakes in the logs, missing files, defaults said aloud.
set(logs --video ${REC}/frames.avi --commands ${REC}/commands.csv --camera ${REC}/camera.xml --plant ${REC}/plant.yml
         --out ${dir}/bad.avi)
file(STRINGS ${REC}/frames.csv lines REGEX "^[0-9]")
set(ms "frame,frame_start,exposure,line_delay\n")
set(exposure_ms "frame,frame_start,exposure,line_delay\n")
set(late "frame,frame_start,exposure,line_delay\n")
foreach(line ${lines})
  string(REPLACE "," ";" f "${line}")
  list(GET f 0 n)
  list(GET f 1 start)
  math(EXPR ms_start "${n} * 100 / 3")  # the same start in ms (33.3 ms per frame)
  string(APPEND ms "${n},${ms_start},0.008,6.94444444e-05\n")
  string(APPEND exposure_ms "${n},${start},8,6.94444444e-05\n")
  string(APPEND late "${n},1${start},0.008,6.94444444e-05\n")  # another epoch: 10 s later (all starts < 10 s)
endforeach()
file(WRITE ${dir}/ms.csv "${ms}")
file(WRITE ${dir}/exposure_ms.csv "${exposure_ms}")
file(WRITE ${dir}/late.csv "${late}")
run(1 ${BIN}/dynblur_restore_video ${logs} --frames ${dir}/exposure_ms.csv)
expect("exposure_ms.csv: frame 0: 'exposure' = 8 s is longer than the frame period 0.0333+ s: seconds expected \\(is it in ms"
       "exposure in ms")
run(1 ${BIN}/dynblur_restore_video ${logs} --frames ${dir}/ms.csv)
expect("'frame_start' steps by 3[34][.0-9]* per frame, a frame period over 1 s: seconds expected \\(is it in ms" "frame_start in ms")
run(1 ${BIN}/dynblur_restore_video ${logs} --frames ${dir}/late.csv)
expect("no frame overlaps a move: the frames span 10 to 12.6[0-9]* s \\(camera clock\\) and the commands 0 to 1.73[0-9]* s"
       "logs on different epochs")
file(WRITE ${dir}/no_line_delay.csv "frame,frame_start,exposure\n0,0.0,0.008\n1,0.0333333,0.008\n")
run(1 ${BIN}/dynblur_restore_video ${logs} --frames ${dir}/no_line_delay.csv --line-delay 62.5)
expect("'line_delay' = 62.5 must be in \\[0, 0.01\\) s: seconds expected \\(is it in us" "a line delay in us")
run(1 ${BIN}/dynblur_restore_video ${logs} --frames ${dir}/no_line_delay.csv --line-delay 0.001)
expect("'line_delay' = 0.001 s reads the 480 rows out in 0.479 s, longer than the frame period 0.0333+ s" "a readout too long")
run(1 ${BIN}/dynblur_restore_video --recording ${dir}/nowhere --out ${dir}/bad.avi)
expect("--recording: the folder '[^']*nowhere' does not exist" "a missing recording folder")
file(MAKE_DIRECTORY ${dir}/partial)
file(COPY ${REC}/frames.avi ${REC}/frames.csv DESTINATION ${dir}/partial)
run(1 ${BIN}/dynblur_restore_video --recording ${dir}/partial --out ${dir}/bad.avi)
expect("--recording: '[^']*partial' lacks commands.csv \\(the command log\\)" "a missing command log")
file(COPY ${REC}/commands.csv DESTINATION ${dir}/partial)
run(1 ${BIN}/dynblur_restore_video --recording ${dir}/partial --out ${dir}/bad.avi)
expect("note: no --camera and no camera.xml in the recording: using the default camera '[^']*c270_nominal.xml'"
       "the default camera is not announced")
expect("--recording: frames are 640x480 but the camera '[^']*c270_nominal.xml' is 1280x960 \\(give the camera that took the video: --camera\\)"
       "a camera of another size")
run(1 ${BIN}/dynblur_restore_video --recording ${REC} --timing ${dir}/nope.yml --out ${dir}/bad.avi)
expect("TimingCalibration::load: cannot open the timing file '[^']*nope.yml'" "a missing timing file")
run(2 ${BIN}/dynblur_restore_video --recording ${REC} --model row --out ${dir}/bad.avi)
expect("--model must be auto, rows, tiles or uniform \\(got 'row'\\)" "an unknown --model")
run(2 ${BIN}/dynblur_restore_video --recording ${REC} --preset fast --out ${dir}/bad.avi)
expect("--preset must be frame-rate or default \\(got 'fast'\\)" "an unknown --preset")
run(2 ${BIN}/dynblur_demo --model row)
expect("--model must be auto, rows, tiles or uniform" "the demo's unknown --model")
if(EXISTS ${dir}/bad.avi)
  message(FATAL_ERROR "a refused restoration left a video behind")
endif()

# --- dynblur_identify_plant: theta logged in degrees.
set(log "t,theta,level\n")
foreach(i RANGE 40)  # one sample a second: the unit of theta is judged before any fit
  if(i LESS 4)
    string(APPEND log "${i},0,0\n")
  else()
    string(APPEND log "${i},4.0,4\n")  # a 4-level step of 1 deg per level, in degrees
  endif()
endforeach()
file(WRITE ${dir}/degrees.csv "${log}")
run(1 ${CALIB}/dynblur_identify_plant ${dir}/degrees.csv --no-png --out ${dir}/bad.yml)
expect("'theta' spans 4 over a move of 4 levels.*radians expected \\(is it logged in degrees" "theta in degrees")
