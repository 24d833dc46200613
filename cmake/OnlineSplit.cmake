# SPDX-License-Identifier: BSD-3-Clause
# The offline/online split of doc/design.md §1-2, enforced at configure time.
#
# flexloop_offline_libraries(<targets>...) names the libraries that hold offline code (the model,
# its parsers, linearisation, analysis, design, scenes, reports). flexloop_require_online(<targets>...)
# fails the configuration if any of the targets links one of them, directly or through another
# library; call it after every target is defined (the top-level CMakeLists does).
set_property(GLOBAL PROPERTY FLEXLOOP_OFFLINE_LIBRARIES "")

function(flexloop_offline_libraries)
  set_property(GLOBAL APPEND PROPERTY FLEXLOOP_OFFLINE_LIBRARIES ${ARGN})
endfunction()

# Every target `target` links, transitively, into the variable `out`.
function(_flexloop_link_closure target out)
  set(seen "")
  set(queue ${target})
  while(queue)
    list(POP_FRONT queue t)
    if(NOT TARGET ${t} OR t IN_LIST seen)
      continue()
    endif()
    list(APPEND seen ${t})
    get_target_property(type ${t} TYPE)
    set(links "")
    if(NOT type STREQUAL "INTERFACE_LIBRARY")
      get_target_property(direct ${t} LINK_LIBRARIES)
      if(direct)
        list(APPEND links ${direct})
      endif()
    endif()
    get_target_property(iface ${t} INTERFACE_LINK_LIBRARIES)
    if(iface)
      list(APPEND links ${iface})
    endif()
    foreach(l IN LISTS links)
      string(REGEX REPLACE "^\\$<LINK_ONLY:(.*)>$" "\\1" l "${l}")
      list(APPEND queue ${l})
    endforeach()
  endwhile()
  set(${out} ${seen} PARENT_SCOPE)
endfunction()

function(flexloop_require_online)
  get_property(offline GLOBAL PROPERTY FLEXLOOP_OFFLINE_LIBRARIES)
  foreach(target IN LISTS ARGN)
    _flexloop_link_closure(${target} closure)
    foreach(lib IN LISTS closure)
      if(lib IN_LIST offline)
        message(FATAL_ERROR "${target} is online code but links the offline library ${lib} "
                            "(doc/design.md §2: online code never depends on the model, the parsers, "
                            "the analysis or the design code)")
      endif()
    endforeach()
  endforeach()
endfunction()

# flexloop_require_without(<library> <targets>...) fails the configuration if any of the targets
# links <library>, directly or through another library (the plant process's side and the FMU
# loader: doc/design.md §2).
function(flexloop_require_without library)
  foreach(target IN LISTS ARGN)
    _flexloop_link_closure(${target} closure)
    if(library IN_LIST closure)
      message(FATAL_ERROR "${target} links ${library} (doc/design.md §2: only the programs that "
                          "run a controller FMU link the FMU loader)")
    endif()
  endforeach()
endfunction()
