# Writes the man page ardrone-gs.1.gz from the program's own --help (help2man), with one section
# per subcommand (its --help) and the environment and files sections.
# cmake -DEXE=<ardrone-gs> -DHELP2MAN=<help2man> -DOUT=<ardrone-gs.1.gz> -P scripts/man_page.cmake
cmake_minimum_required(VERSION 3.25)
get_filename_component(work "${OUT}" DIRECTORY)

# The subcommands: the names under "Subcommands:" in a --help text, one per line.
function(subcommands_of help out)
  string(REGEX MATCH "[Ss]ubcommands:\n(.*)" tail "${help}")
  set(names "")
  if(tail)
    string(REPLACE "\n" ";" lines "${CMAKE_MATCH_1}")
    foreach(line IN LISTS lines)
      if(line MATCHES "^  ([a-z][a-z0-9-]*)( |$)")
        list(APPEND names "${CMAKE_MATCH_1}")
      elseif(NOT line MATCHES "^ " AND NOT line STREQUAL "")
        break()
      endif()
    endforeach()
  endif()
  set(${out} "${names}" PARENT_SCOPE)
endfunction()

function(roff_escape text out)
  string(REPLACE "\\" "\\e" text "${text}")
  string(REGEX REPLACE "(^|\n)([.'])" "\\1\\\\&\\2" text "${text}")
  set(${out} "${text}" PARENT_SCOPE)
endfunction()

execute_process(COMMAND "${EXE}" --help OUTPUT_VARIABLE root_help RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "${EXE} --help failed (${rc})")
endif()
subcommands_of("${root_help}" commands)

set(inc "[SUBCOMMANDS]\nEach subcommand's options, as its --help prints them.\n")
foreach(cmd IN LISTS commands)
  execute_process(COMMAND "${EXE}" ${cmd} --help OUTPUT_VARIABLE help RESULT_VARIABLE rc)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "${EXE} ${cmd} --help failed (${rc})")
  endif()
  subcommands_of("${help}" children)
  set(pages "${cmd}")
  foreach(child IN LISTS children)
    list(APPEND pages "${cmd} ${child}")
  endforeach()
  foreach(page IN LISTS pages)
    string(REPLACE " " ";" argv "${page}")
    execute_process(COMMAND "${EXE}" ${argv} --help OUTPUT_VARIABLE help RESULT_VARIABLE rc)
    if(NOT rc EQUAL 0)
      message(FATAL_ERROR "${EXE} ${page} --help failed (${rc})")
    endif()
    roff_escape("${help}" help)
    string(APPEND inc ".SS \"ardrone-gs ${page}\"\n.nf\n${help}.fi\n")
  endforeach()
endforeach()
string(APPEND inc "
[ENVIRONMENT]
.TP
.B ARDRONE_GS_ASSETS
The folder holding the camera calibrations and the virtual drone's scenes, instead of the
installed one. The program stops with an error when it names no folder.
[FILES]
.TP
.I <prefix>/share/ardrone-gs/
Camera calibrations (calibration/) and virtual-drone scenes (scenes/), found relative to the
installed program.
")
file(WRITE "${work}/ardrone-gs.h2m" "${inc}")

get_filename_component(page "${OUT}" NAME_WLE)
execute_process(
  COMMAND "${HELP2MAN}" --no-info --section=1
          "--name=ground station for the Parrot AR.Drone 2.0"
          "--include=${work}/ardrone-gs.h2m" "--output=${work}/${page}" "${EXE}"
  RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "help2man failed (${rc})")
endif()
# gzip -n: no name or time in the header, so the same program gives the same file.
execute_process(COMMAND gzip -9nf "${work}/${page}" RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "gzip failed (${rc})")
endif()
