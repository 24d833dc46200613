# SPDX-License-Identifier: BSD-3-Clause
# `cmake --install` and the CPack .deb (doc/install.md): the programs, the C controller library with
# its headers, pkg-config and CMake package files, the scenes, models, controllers and examples, and
# a man page per program from its --help. Included after the subdirectories define the targets.
include(CMakePackageConfigHelpers)

set(flexloop_programs flexloop flexloop-plant flexloop-controller flexloop-c-controller)
# The C example links the shared C controller library: found beside it, wherever the prefix is.
file(RELATIVE_PATH libdir_from_bindir ${CMAKE_INSTALL_PREFIX}/${CMAKE_INSTALL_BINDIR}
  ${CMAKE_INSTALL_PREFIX}/${CMAKE_INSTALL_LIBDIR})
set_target_properties(flexloop-c-controller PROPERTIES INSTALL_RPATH "$ORIGIN/${libdir_from_bindir}")
install(TARGETS ${flexloop_programs} EXPORT flexloopTargets
  RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
# The plant FMU's library, which `flexloop export-fmu` zips (tools/flexloop/cmd_export_fmu.cpp).
install(TARGETS flexloop_plant LIBRARY DESTINATION ${FLEXLOOP_INSTALL_PLUGINDIR})

# Scenes name their models and controller files relative to themselves (../models/...): the same
# tree under share/flexloop keeps them working.
install(DIRECTORY tools/scenes tools/models tools/controllers DESTINATION ${FLEXLOOP_INSTALL_DATADIR}
  USE_SOURCE_PERMISSIONS)
install(FILES LICENSE NOTICE README.md DESTINATION ${CMAKE_INSTALL_DOCDIR})

# pkg-config: the prefix is found from the .pc file's own place.
file(RELATIVE_PATH FLEXLOOP_PC_PREFIX_FROM_PCDIR
  ${CMAKE_INSTALL_PREFIX}/${CMAKE_INSTALL_LIBDIR}/pkgconfig ${CMAKE_INSTALL_PREFIX})
string(REGEX REPLACE "/$" "" FLEXLOOP_PC_PREFIX_FROM_PCDIR "${FLEXLOOP_PC_PREFIX_FROM_PCDIR}")
configure_file(${CMAKE_CURRENT_LIST_DIR}/flexloop.pc.in ${CMAKE_BINARY_DIR}/flexloop.pc @ONLY)
install(FILES ${CMAKE_BINARY_DIR}/flexloop.pc DESTINATION ${CMAKE_INSTALL_LIBDIR}/pkgconfig)

# CMake: find_package(flexloop) -> flexloop::c_controller and the programs.
install(EXPORT flexloopTargets NAMESPACE flexloop:: DESTINATION ${FLEXLOOP_INSTALL_CMAKEDIR})
configure_package_config_file(${CMAKE_CURRENT_LIST_DIR}/flexloopConfig.cmake.in
  ${CMAKE_BINARY_DIR}/flexloopConfig.cmake INSTALL_DESTINATION ${FLEXLOOP_INSTALL_CMAKEDIR}
  PATH_VARS FLEXLOOP_INSTALL_DATADIR)
# 0.x: a new minor version may change the interface.
write_basic_package_version_file(${CMAKE_BINARY_DIR}/flexloopConfigVersion.cmake
  COMPATIBILITY SameMinorVersion)
install(FILES ${CMAKE_BINARY_DIR}/flexloopConfig.cmake ${CMAKE_BINARY_DIR}/flexloopConfigVersion.cmake
  DESTINATION ${FLEXLOOP_INSTALL_CMAKEDIR})

# Man pages: help2man runs each program's --help (the version given, as none has --version).
find_program(HELP2MAN_EXECUTABLE help2man)
if(HELP2MAN_EXECUTABLE)
  set(man_dir ${CMAKE_BINARY_DIR}/man)
  set(man_pages)
  set(man_name_flexloop "finite-element model to real-time loop: analyse, build, sim, hil")
  set(man_name_flexloop-plant "the plant process of the real-time loop")
  set(man_name_flexloop-controller "the controller process of the real-time loop")
  set(man_name_flexloop-c-controller "external state-space controller in plain C")
  # flexloop's page has every subcommand's options, not only their list.
  set(man_help_flexloop --help-all)
  foreach(program ${flexloop_programs})
    add_custom_command(OUTPUT ${man_dir}/${program}.1
      COMMAND ${CMAKE_COMMAND} -E make_directory ${man_dir}
      COMMAND ${HELP2MAN_EXECUTABLE} --no-info --no-discard-stderr
              --help-option=$<IF:$<BOOL:${man_help_${program}}>,${man_help_${program}},--help>
              --version-string=${PROJECT_VERSION} "--name=${man_name_${program}}"
              --output=${man_dir}/${program}.1 $<TARGET_FILE:${program}>
      DEPENDS ${program}
      COMMENT "help2man ${program}"
      VERBATIM)
    list(APPEND man_pages ${man_dir}/${program}.1)
  endforeach()
  add_custom_target(flexloop_man ALL DEPENDS ${man_pages})
  install(FILES ${man_pages} DESTINATION ${CMAKE_INSTALL_MANDIR}/man1)
else()
  message(WARNING "help2man not found: no man pages installed (tools/lib/common.sh installs it)")
endif()

# What `cmake --install` and cpack need, without the tests and benchmarks that ALL also builds:
# `cmake --build DIR --target installables`.
add_custom_target(installables)
add_dependencies(installables ${flexloop_programs} flexloop_c_controller flexloop_plant)
if(TARGET flexloop_python)  # where pybind11 is installed (tools/python)
  add_dependencies(installables flexloop_python)
endif()
if(TARGET flexloop_man)
  add_dependencies(installables flexloop_man)
endif()

# The .deb: `cpack -G DEB` in the build directory. Its dependencies are read from the binaries
# (dpkg-shlibdeps). A native build (FLEXLOOP_NATIVE, the default on x86) runs only on CPUs with
# the building machine's instruction set: its version says +native and its description says so;
# a package for other machines is built with -DFLEXLOOP_NATIVE=OFF.
set(CPACK_GENERATOR DEB)
set(CPACK_PACKAGE_NAME flexloop)
set(CPACK_PACKAGE_VERSION ${PROJECT_VERSION})
set(CPACK_PACKAGE_CONTACT "flexloop maintainers <flexloop@localhost>")
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY
  "finite-element multibody model to a linearised plant run in a hard real-time loop")
# The long description, after the summary line (CPack indents it).
set(CPACK_PACKAGE_DESCRIPTION "The programs flexloop, flexloop-plant, flexloop-controller and
flexloop-c-controller, the C controller library (libflexloop_c_controller, <flexloop/carrier.h>,
flexloop.pc, CMake package flexloop), and the scenes, models and examples in /usr/share/flexloop.")
if(FLEXLOOP_NATIVE)
  string(APPEND CPACK_PACKAGE_DESCRIPTION "
Built with -march=native: it runs only on CPUs with the instruction set of the machine that
built it.")
  set(CPACK_DEBIAN_PACKAGE_VERSION ${PROJECT_VERSION}+native)
endif()
set(CPACK_DEBIAN_PACKAGE_SECTION science)
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
# The installed headers include LCM's; the C example also needs cJSON's.
set(CPACK_DEBIAN_PACKAGE_RECOMMENDS "liblcm-dev, libcjson-dev, pkg-config")
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
include(CPack)
