# SPDX-License-Identifier: BSD-3-Clause
# Version, git hash and compiler for `flexloop version` and provenance, written at configure time.
execute_process(
  COMMAND git rev-parse --short=12 HEAD
  WORKING_DIRECTORY ${CMAKE_SOURCE_DIR}
  OUTPUT_VARIABLE FLEXLOOP_GIT_HASH OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET)
execute_process(
  COMMAND git status --porcelain --untracked-files=no
  WORKING_DIRECTORY ${CMAKE_SOURCE_DIR}
  OUTPUT_VARIABLE _dirty OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET)
if(NOT FLEXLOOP_GIT_HASH)
  set(FLEXLOOP_GIT_HASH "unknown")
elseif(_dirty)
  string(APPEND FLEXLOOP_GIT_HASH "-dirty")
endif()
# A source file, not a header: only it recompiles when the hash changes (common/build_info.hpp).
configure_file(${CMAKE_SOURCE_DIR}/cmake/build_info.cpp.in
               ${CMAKE_BINARY_DIR}/generated/build_info.cpp @ONLY)
add_library(flexloop_build_info STATIC ${CMAKE_BINARY_DIR}/generated/build_info.cpp)
target_include_directories(flexloop_build_info PUBLIC ${CMAKE_SOURCE_DIR})
