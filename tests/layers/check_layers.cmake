# The include direction of the library (ARCHITECTURE.md, "Layers"): a header may include headers
# of its own folder and of folders on a lower layer, never of its own layer's other folders or of
# a higher one, so the folders form no cycle. Also: no header longer than MAX_LINES (if given).
#   cmake -DROOT=<folder holding micromacro/> [-DMAX_LINES=400] -P check_layers.cmake
# Fails with one line per offending include.
cmake_minimum_required(VERSION 3.21)
if(NOT ROOT)
  message(FATAL_ERROR "check_layers.cmake: give -DROOT=<folder that holds micromacro/>")
endif()

# Folder -> layer, bottom first. The umbrella header micromacro.hpp sits above everything.
set(layer_core 0)
set(layer_particles 1)
set(layer_contact 1)
set(layer_walls 1)
set(layer_neighbors 1)
set(layer_integrators 1)
set(layer_forces 2)       # body forces act on particles
set(layer_averaging 1)    # a frozen snapshot: it needs the core only
set(layer_engine 3)       # the simulation and what runs one (snapshots of it, probes)
set(layer_io 4)
set(layer_mpi 5)       # domain decomposition over MPI ranks (optional, needs MPI), its output through io/
set(layer_umbrella 6)

function(folder_of path out)  # micromacro/<folder>/x.hpp -> folder; micromacro/x.hpp -> umbrella
  string(REGEX MATCH "^micromacro/([^/]+)/" match "${path}")
  if(match)
    set(${out} "${CMAKE_MATCH_1}" PARENT_SCOPE)
  else()
    set(${out} umbrella PARENT_SCOPE)
  endif()
endfunction()

file(GLOB_RECURSE headers RELATIVE ${ROOT} ${ROOT}/micromacro/*.hpp)
if(NOT headers)
  message(FATAL_ERROR "check_layers.cmake: no headers under ${ROOT}/micromacro")
endif()
set(problems "")
set(checked 0)
foreach(header IN LISTS headers)
  folder_of(${header} from)
  if(NOT DEFINED layer_${from})
    string(APPEND problems "  ${header}: folder '${from}' has no layer; add it to tests/layers/check_layers.cmake and ARCHITECTURE.md\n")
    continue()
  endif()
  file(READ ${ROOT}/${header} text)
  string(REGEX MATCHALL "\n" newlines "${text}")
  list(LENGTH newlines line_count)
  file(STRINGS ${ROOT}/${header} lines REGEX "^[ \t]*#[ \t]*include")
  if(MAX_LINES AND line_count GREATER MAX_LINES)
    string(APPEND problems "  ${header}: ${line_count} lines, more than ${MAX_LINES}; split it by job\n")
  endif()
  foreach(line IN LISTS lines)
    if(line MATCHES "^[ \t]*#[ \t]*include[ \t]*[\"<](micromacro/[^\">]+)[\">]")
      set(target ${CMAKE_MATCH_1})
      math(EXPR checked "${checked} + 1")
      folder_of(${target} to)
      if(to STREQUAL from)
        continue()
      endif()
      if(NOT DEFINED layer_${to})
        string(APPEND problems "  ${header} includes ${target}: folder '${to}' has no layer\n")
      elseif(NOT layer_${to} LESS layer_${from})
        string(APPEND problems "  ${header} (layer ${layer_${from}}, ${from}/) includes ${target} (layer ${layer_${to}}, ${to}/): "
                               "a header may include only its own folder and lower layers\n")
      endif()
    endif()
  endforeach()
endforeach()
if(problems)
  message(FATAL_ERROR "the library's headers break the layering (ARCHITECTURE.md, \"Layers\"):\n${problems}")
endif()
list(LENGTH headers header_count)
message(STATUS "layers: ${header_count} headers, ${checked} includes, all downward")
