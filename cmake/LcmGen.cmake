# SPDX-License-Identifier: BSD-3-Clause
# flexloop_lcm_gen(TARGET <name> PACKAGE <pkg> FILES a.lcm b.lcm ...)
# Runs lcm-gen at build time and exposes the generated C++ headers through an INTERFACE target.
function(flexloop_lcm_gen)
  cmake_parse_arguments(ARG "" "TARGET;PACKAGE" "FILES" ${ARGN})
  set(out_dir ${CMAKE_CURRENT_BINARY_DIR}/lcmgen)
  set(headers)
  foreach(lcm_file IN LISTS ARG_FILES)
    get_filename_component(stem ${lcm_file} NAME_WE)
    set(hdr ${out_dir}/${ARG_PACKAGE}/${stem}.hpp)
    add_custom_command(
      OUTPUT ${hdr}
      COMMAND ${LCM_GEN_EXECUTABLE} --cpp --cpp-hpath ${out_dir} --cpp-std=c++11
              ${CMAKE_CURRENT_SOURCE_DIR}/${lcm_file}
      DEPENDS ${CMAKE_CURRENT_SOURCE_DIR}/${lcm_file}
      COMMENT "lcm-gen ${lcm_file}"
      VERBATIM)
    list(APPEND headers ${hdr})
  endforeach()
  add_custom_target(${ARG_TARGET}_gen DEPENDS ${headers})
  add_library(${ARG_TARGET} INTERFACE)
  add_dependencies(${ARG_TARGET} ${ARG_TARGET}_gen)
  target_include_directories(${ARG_TARGET} SYSTEM INTERFACE ${out_dir})
  target_link_libraries(${ARG_TARGET} INTERFACE flexloop_lcm)
endfunction()
