# flexloop_area_library(<target> DIR <folder> [LINK <targets>...])
# One library per area folder: every .cpp in the folder becomes part of it; a folder with
# headers only gives an INTERFACE library. Include paths are rooted at the repository, so code
# includes "plant/lti/state_space.hpp" and the folder in the path tells offline from online.
function(flexloop_area_library target)
  cmake_parse_arguments(ARG "" "DIR" "LINK" ${ARGN})
  file(GLOB sources CONFIGURE_DEPENDS ${CMAKE_SOURCE_DIR}/${ARG_DIR}/*.cpp)
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
