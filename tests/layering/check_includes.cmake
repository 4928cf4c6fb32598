# The layering rules, checked on the sources: every project #include of a folder's files must name
# a folder that folder may use. Run by CTest (Layering.IncludesFollowTheLayers):
#   cmake -DGS_SOURCE_DIR=<repo> -P tests/layering/check_includes.cmake
#
#   drone/core       the base: nothing of ours
#   drone/protocol   core                  drone/transport  core
#   drone/video      core protocol         drone/link       core protocol transport video
#   drone/dataset    core protocol video   drone/record     core protocol video link dataset
#   drone/sim        core protocol transport video link dataset record (the virtual drone;
#                    nothing below it includes sim; it names the link only to build the
#                    LinkConfig that reaches it, drone/sim/loopback.hpp)
#   vision           drone/core only       ui               drone/core drone/protocol vision
#   app              anything
# and no file outside ui/ and app's GUI part (app/gui_*, app/cmd_gui.cpp) includes ImGui, GLFW or
# OpenGL headers.

cmake_minimum_required(VERSION 3.25)

if(NOT GS_SOURCE_DIR)
  message(FATAL_ERROR "pass -DGS_SOURCE_DIR=<repository root>")
endif()

set(allowed_drone/core "drone/core")
set(allowed_drone/protocol "drone/core;drone/protocol")
set(allowed_drone/transport "drone/core;drone/transport")
set(allowed_drone/video "drone/core;drone/protocol;drone/video")
set(allowed_drone/link "drone/core;drone/protocol;drone/transport;drone/video;drone/link")
set(allowed_drone/dataset "drone/core;drone/protocol;drone/video;drone/dataset")
set(allowed_drone/record "drone/core;drone/protocol;drone/video;drone/link;drone/dataset;drone/record")
set(allowed_drone/sim
    "drone/core;drone/protocol;drone/transport;drone/video;drone/link;drone/dataset;drone/record;drone/sim")
set(allowed_vision "drone/core;vision")
set(allowed_ui "drone/core;drone/protocol;vision;ui")

set(violations "")
set(checked 0)
foreach(layer drone/core drone/protocol drone/transport drone/video drone/link drone/dataset
              drone/record drone/sim vision ui app)
  file(GLOB files ${GS_SOURCE_DIR}/${layer}/*.cpp ${GS_SOURCE_DIR}/${layer}/*.hpp)
  if(NOT files)
    list(APPEND violations "${layer}: no sources found (the layout changed: update this check)")
  endif()
  foreach(f ${files})
    math(EXPR checked "${checked} + 1")
    file(RELATIVE_PATH rel ${GS_SOURCE_DIR} ${f})
    file(STRINGS ${f} includes REGEX "^[ \t]*#[ \t]*include[ \t]*[\"<]")
    foreach(line ${includes})
      string(REGEX REPLACE "^[ \t]*#[ \t]*include[ \t]*[\"<]([^\">]+)[\">].*$" "\\1" inc "${line}")
      # ImGui, GLFW, OpenGL: ui/ and app's GUI part only.
      if(inc MATCHES "^(imgui|GLFW/|GL/|backends/imgui)")
        if(NOT layer STREQUAL "ui" AND NOT rel MATCHES "^app/(gui_|cmd_gui)")
          list(APPEND violations "${rel}: includes <${inc}> (only ui/ and app's GUI part may)")
        endif()
        continue()
      endif()
      # Our own headers: <top>/<folder>/x.hpp for drone/, <top>/x.hpp otherwise.
      if(inc MATCHES "^drone/([a-z_]+)/")
        set(target "drone/${CMAKE_MATCH_1}")
      elseif(inc MATCHES "^(vision|ui|app)/")
        set(target "${CMAKE_MATCH_1}")
      elseif(inc MATCHES "^drone/")
        list(APPEND violations "${rel}: includes ${inc}: drone/ has no files at its top")
        continue()
      else()
        continue()
      endif()
      if(layer STREQUAL "app")
        continue()
      endif()
      if(NOT target IN_LIST allowed_${layer})
        list(APPEND violations "${rel}: includes ${inc} (${layer} may use: ${allowed_${layer}})")
      endif()
    endforeach()
  endforeach()
endforeach()

# drone/ is one level deep: no source files at its top, none two levels down.
file(GLOB top ${GS_SOURCE_DIR}/drone/*.cpp ${GS_SOURCE_DIR}/drone/*.hpp)
file(GLOB deep ${GS_SOURCE_DIR}/drone/*/*/*.cpp ${GS_SOURCE_DIR}/drone/*/*/*.hpp)
foreach(f ${top} ${deep})
  file(RELATIVE_PATH rel ${GS_SOURCE_DIR} ${f})
  list(APPEND violations "${rel}: drone/ sources live exactly one folder deep")
endforeach()

list(LENGTH violations n)
if(n GREATER 0)
  string(REPLACE ";" "\n  " text "${violations}")
  message(FATAL_ERROR "${n} layering violation(s):\n  ${text}")
endif()
message(STATUS "layering: ${checked} files follow the rules")
