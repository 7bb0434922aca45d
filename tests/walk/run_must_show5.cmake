# Must-show 5 (issue 5) under Xvfb: the same input script walked at a render rate of 10 and of 60
# frames per simulated second (--fps: frame k at k/N s; the simulation runs fixed 1/120 s steps)
# must reach the same poses at equal path times within 1 mm and 0.01 deg (recorded camera paths
# compared by walk_path_compare).  Then the 10 fps recording is replayed at 20 fps (--replay) and
# re-recorded: the replay must pass through the recorded keyframes within the same tolerance.
# Also checks the scripted screenshot (EXR + PNG) and the recordings' validity as camera paths.
# -DPRW=prw -DCOMPARE=walk_path_compare -DSCRIPT=file -DWORK=dir
find_program(XVFB xvfb-run)
if(NOT XVFB)
  message("skipped: xvfb-run not installed (scripts/setup.sh installs it)")
  return()
endif()
file(REMOVE_RECURSE ${WORK})
file(MAKE_DIRECTORY ${WORK})
set(XV ${XVFB} -a -s "-screen 0 640x480x24")
set(COMMON walk --size 128x96 --msaa 1 --shadow-size 256 --input-script ${SCRIPT} --shot-dir ${WORK}/shots)

function(run_prw name)
  execute_process(COMMAND ${XV} ${PRW} ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err TIMEOUT 300)
  message("[${name}] rc=${rc}\n${out}${err}")
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "${name}: prw walk failed (rc ${rc})")
  endif()
  set(last_out "${out}" PARENT_SCOPE)
endfunction()

run_prw(walk10 ${COMMON} --fps 10 --record ${WORK}/walk10.json)
if(NOT last_out MATCHES "screenshot: wrote .*walk_t1666.exr .*walk_t1666.png.*recorded 21 keyframes")
  message(FATAL_ERROR "walk10: expected the screenshot and 21 keyframes")
endif()
foreach(f ${WORK}/shots/walk_t1666.exr ${WORK}/shots/walk_t1666.png)
  if(NOT EXISTS ${f})
    message(FATAL_ERROR "missing screenshot ${f}")
  endif()
endforeach()
file(REMOVE_RECURSE ${WORK}/shots)
run_prw(walk60 ${COMMON} --fps 60 --no-pass-times --record ${WORK}/walk60.json) # timestamps flush on lavapipe
if(NOT last_out MATCHES "recorded 121 keyframes")
  message(FATAL_ERROR "walk60: expected 121 keyframes")
endif()

execute_process(COMMAND ${COMPARE} ${WORK}/walk10.json ${WORK}/walk60.json 0.001 0.01 20 0.5 RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "10 fps and 60 fps walks differ")
endif()

run_prw(replay walk --size 128x96 --msaa 1 --shadow-size 256 --no-hud --no-pass-times --replay ${WORK}/walk10.json --fps 20
        --record ${WORK}/replay.json)
execute_process(COMMAND ${COMPARE} ${WORK}/walk10.json ${WORK}/replay.json 0.001 0.01 20 0.5 RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "the replay does not pass through the recorded poses")
endif()
