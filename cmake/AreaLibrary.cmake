# SPDX-License-Identifier: BSD-3-Clause
# flexloop_area_library(<target> DIR <folder> [FILES <names>...] [EXCLUDE <names>...]
#                       [LINK <targets>...])
# One library per area folder: every .cpp in the folder becomes part of it; a folder with
# headers only gives an INTERFACE library. Include paths are rooted at the repository, so code
# includes "plant/lti/state_space.hpp" and the folder in the path tells offline from online.
# A folder whose programs do not all need all of it is split: FILES takes only the named .cpp
# files of the folder, EXCLUDE leaves the named ones out (online/loop: the controller process's
# loop, which runs a controller FMU, apart from what the plant process links).
function(flexloop_area_library target)
  cmake_parse_arguments(ARG "" "DIR" "FILES;EXCLUDE;LINK" ${ARGN})
  if(ARG_FILES)
    list(TRANSFORM ARG_FILES PREPEND ${CMAKE_SOURCE_DIR}/${ARG_DIR}/ OUTPUT_VARIABLE sources)
  else()
    file(GLOB sources CONFIGURE_DEPENDS ${CMAKE_SOURCE_DIR}/${ARG_DIR}/*.cpp)
  endif()
  foreach(name IN LISTS ARG_EXCLUDE)
    list(REMOVE_ITEM sources ${CMAKE_SOURCE_DIR}/${ARG_DIR}/${name})
  endforeach()
  if(sources)
    add_library(${target} STATIC ${sources})
    target_include_directories(${target} PUBLIC ${CMAKE_SOURCE_DIR})
    target_link_libraries(${target} PUBLIC ${ARG_LINK})
  else()
    add_library(${target} INTERFACE)
    target_include_directories(${target} INTERFACE ${CMAKE_SOURCE_DIR})
    target_link_libraries(${target} INTERFACE ${ARG_LINK})
  endif()
endfunction()
