# The render core's structural rules (issue "Render core", must-show 5), checked on the sources:
#  1. a pass file (engine/render/pass_*.c) exports nothing but its `const prw_pass prw_pass_*`
#     descriptor(s): every other function is static, so no file can call a pass file's function;
#  2. barriers and layout transitions of graph images come only from the graph: outside graph.c, no
#     file of engine/render records vkCmdPipelineBarrier* or prw_cmd_transition, except the
#     standalone users of images the graph does not own (compose.c: prw_composer_run on uploaded
#     images; tonemap_gpu.c: tone-mapping sessions on their own images, and the barriers between a
#     pass's own dispatches go through prw_pass_* there).
#   cmake -DSRC=<repo>/engine/render -P cmake/check_render_passes.cmake
file(GLOB passes ${SRC}/pass_*.c)
set(bad "")
foreach(f IN LISTS passes)
  file(STRINGS ${f} lines)
  foreach(l IN LISTS lines)
    # a definition or declaration at file scope that is neither static nor the descriptor
    if(l MATCHES "^[A-Za-z_][A-Za-z0-9_ \\*]*[ \\*]([A-Za-z_][A-Za-z0-9_]*)\\(" AND NOT l MATCHES "^static" AND NOT l MATCHES "^typedef")
      string(APPEND bad "${f}: exported function: ${l}\n")
    endif()
    if(l MATCHES "^const prw_pass " AND NOT l MATCHES "^const prw_pass prw_pass_[a-z0-9_]+ = {")
      string(APPEND bad "${f}: a descriptor not named prw_pass_*: ${l}\n")
    endif()
  endforeach()
endforeach()
file(GLOB all ${SRC}/*.c)
foreach(f IN LISTS all)
  get_filename_component(n ${f} NAME)
  if(n STREQUAL "graph.c" OR n STREQUAL "compose.c" OR n STREQUAL "tonemap_gpu.c")
    continue()
  endif()
  file(STRINGS ${f} hits REGEX "vkCmdPipelineBarrier|prw_cmd_transition")
  foreach(h IN LISTS hits)
    string(APPEND bad "${f}: a barrier outside the graph: ${h}\n")
  endforeach()
endforeach()
list(LENGTH passes np)
if(np LESS 8)
  string(APPEND bad "only ${np} pass files found in ${SRC}: wrong directory?\n")
endif()
if(bad)
  message(FATAL_ERROR "render core rules broken:\n${bad}")
endif()
message("render core rules hold: ${np} pass files export only their descriptors; barriers only in graph.c")
