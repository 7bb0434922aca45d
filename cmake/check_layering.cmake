# The layering check (ctest `layering`): cmake -DGRAPH=<link_graph.cmake> -P check_layering.cmake
#
# DESIGN.md §3: app -> engine -> (lod, materials) -> core, and inside engine
# bake -> (render, reference) -> (scene, view, gpu, image).  Every target defined in one of the
# ranked folders below may link (directly or through any chain of targets, PRIVATE or PUBLIC)
# only targets of its own rank or lower; reaching a target defined in a higher-ranked folder fails,
# printing the chain.  So engine/render and engine/reference never reach a baker in engine/bake
# (the renderer and the reference only use what was baked before), and lod/, materials/ and core/
# never reach engine/.  Folders not listed (app, assets, shaders, engine/metrics, tests) are not
# checked themselves, but chains through their targets count.
cmake_minimum_required(VERSION 3.25) # IN_LIST, POP_FRONT
set(PRW_RANKS
  "core=0"
  "lod=1" "materials=1" "materials/btf=1" "materials/env=1"
  "engine/scene=2" "engine/view=2" "engine/gpu=2" "engine/image=2"
  "engine/render=3" "engine/reference=3"
  "engine/bake=4")
# Sanity edges that must exist (so an empty or broken graph cannot pass): "from>to".
set(PRW_MUST_REACH "prw_render>prw_core" "prw_render>prw_scene" "prw_reference>prw_scene" "prw_bake>prw_scene"
  "prw>prw_bake" "prw>prw_render" "prw>prw_reference")

if(NOT GRAPH OR NOT EXISTS "${GRAPH}")
  message(FATAL_ERROR "layering: no link graph '${GRAPH}' (re-run cmake)")
endif()
include(${GRAPH})

function(rank_of folder out)
  set(r "")
  foreach(kv IN LISTS PRW_RANKS)
    string(REPLACE "=" ";" kv "${kv}")
    list(GET kv 0 f)
    list(GET kv 1 n)
    if(folder STREQUAL f)
      set(r ${n})
    endif()
  endforeach()
  set(${out} "${r}" PARENT_SCOPE)
endfunction()

# Breadth-first walk from `start`; sets <out>_reached and, per reached target t, PARENT_<t>.
macro(walk start out)
  set(${out}_reached "")
  set(queue ${start})
  set(seen ${start})
  while(queue)
    list(POP_FRONT queue cur)
    foreach(d IN LISTS PRW_GRAPH_DEPS_${cur})
      if(NOT d IN_LIST seen)
        list(APPEND seen ${d})
        set(PARENT_${d} ${cur})
        list(APPEND ${out}_reached ${d})
        if(d IN_LIST PRW_GRAPH_TARGETS)
          list(APPEND queue ${d})
        endif()
      endif()
    endforeach()
  endwhile()
endmacro()

function(chain start to out)
  set(c ${to})
  set(cur ${to})
  while(NOT cur STREQUAL start)
    set(cur ${PARENT_${cur}})
    set(c "${cur} -> ${c}")
  endwhile()
  set(${out} "${c}" PARENT_SCOPE)
endfunction()

set(bad 0)
set(checked 0)
foreach(t IN LISTS PRW_GRAPH_TARGETS)
  rank_of("${PRW_GRAPH_FOLDER_${t}}" rt)
  if(rt STREQUAL "")
    continue()
  endif()
  math(EXPR checked "${checked} + 1")
  walk(${t} w)
  set(prw_reached "")
  foreach(d IN LISTS w_reached)
    if(NOT d IN_LIST PRW_GRAPH_TARGETS)
      continue() # system / imported library
    endif()
    list(APPEND prw_reached ${d})
    rank_of("${PRW_GRAPH_FOLDER_${d}}" rd)
    if(NOT rd STREQUAL "" AND rd GREATER rt)
      chain(${t} ${d} c)
      message(SEND_ERROR "layering: ${t} (${PRW_GRAPH_FOLDER_${t}}) links ${d} (${PRW_GRAPH_FOLDER_${d}}), which is above it "
                         "(DESIGN.md §3): ${c}")
      math(EXPR bad "${bad} + 1")
    endif()
  endforeach()
  list(JOIN prw_reached ", " j)
  message(STATUS "${t} (${PRW_GRAPH_FOLDER_${t}}): reaches ${j}")
endforeach()

foreach(e IN LISTS PRW_MUST_REACH)
  string(REPLACE ">" ";" e "${e}")
  list(GET e 0 from)
  list(GET e 1 to)
  if(NOT from IN_LIST PRW_GRAPH_TARGETS OR NOT to IN_LIST PRW_GRAPH_TARGETS)
    continue() # a partial build (PRW_MODULES) without one of them
  endif()
  walk(${from} s)
  if(NOT to IN_LIST s_reached)
    message(SEND_ERROR "layering: sanity: ${from} should reach ${to}; is the link graph complete?")
    math(EXPR bad "${bad} + 1")
  endif()
endforeach()

if(checked EQUAL 0)
  message(FATAL_ERROR "layering: no target in a ranked folder: the link graph is empty")
endif()
if(bad GREATER 0)
  message(FATAL_ERROR "layering: ${bad} violation(s)")
endif()
message(STATUS "layering: ${checked} targets checked, no link goes up a layer")
