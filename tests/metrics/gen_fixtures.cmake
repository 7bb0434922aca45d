# Writes the EXR inputs of the `prw compare` command-line tests: -DTOOL=prw_metric_tool -DDIR=dir
file(MAKE_DIRECTORY ${DIR})
foreach(spec
    "ref.exr;160;120;1;0.05;7.5"
    "ref2.exr;160;120;2;0.05;7.5"
    "good.exr;160;120;3;0.06;-"
    "bad.exr;160;120;4;0.30;-"
    "noev.exr;160;120;5;0.05;-"
    "nan.exr;160;120;6;0.05;7.5;nan"
    "inf.exr;160;120;6;0.05;7.5;inf"
    "small.exr;100;120;7;0.05;7.5")
  list(GET spec 0 name)
  list(SUBLIST spec 1 -1 args)
  execute_process(COMMAND ${TOOL} gen ${DIR}/${name} ${args} RESULT_VARIABLE rc)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "gen ${name} failed: ${rc}")
  endif()
endforeach()
