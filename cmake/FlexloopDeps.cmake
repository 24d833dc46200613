# SPDX-License-Identifier: BSD-3-Clause
# System dependencies, found once for the whole tree. Eigen and LCM headers are SYSTEM includes
# so their warnings never fail our -Werror build.
find_package(Eigen3 3.4 REQUIRED NO_MODULE)
find_package(Threads REQUIRED)

# Debian's LCM 1.3.1 ships no CMake package: find the library, header and code generator.
find_library(LCM_LIBRARY NAMES lcm REQUIRED)
find_path(LCM_INCLUDE_DIR NAMES lcm/lcm-cpp.hpp REQUIRED)
find_program(LCM_GEN_EXECUTABLE NAMES lcm-gen REQUIRED)
add_library(flexloop_lcm INTERFACE)
target_include_directories(flexloop_lcm SYSTEM INTERFACE ${LCM_INCLUDE_DIR})
target_link_libraries(flexloop_lcm INTERFACE ${LCM_LIBRARY} Threads::Threads)

add_library(flexloop_eigen INTERFACE)
target_link_libraries(flexloop_eigen INTERFACE Eigen3::Eigen)
get_target_property(_eigen_inc Eigen3::Eigen INTERFACE_INCLUDE_DIRECTORIES)
target_include_directories(flexloop_eigen SYSTEM INTERFACE ${_eigen_inc})

# Boost.Random (header-only): the ziggurat normal distribution of the noise sources. CONFIG:
# Boost's own package file (libboost-dev ships it); CMake's FindBoost module is deprecated
# (policy CMP0167).
find_package(Boost 1.74 REQUIRED CONFIG COMPONENTS headers)
add_library(flexloop_boost INTERFACE)
get_target_property(_boost_inc Boost::headers INTERFACE_INCLUDE_DIRECTORIES)
target_include_directories(flexloop_boost SYSTEM INTERFACE ${_boost_inc})

if(FLEXLOOP_TESTS OR FLEXLOOP_BENCHMARKS)
  find_package(Catch2 2.13 REQUIRED)
  include(Catch)
endif()
find_package(nlohmann_json 3 REQUIRED)
find_path(TOMLPP_INCLUDE_DIR NAMES toml++/toml.h REQUIRED)
find_path(CLI11_INCLUDE_DIR NAMES CLI/CLI.hpp REQUIRED)
if(FLEXLOOP_BENCHMARKS)
  find_package(benchmark REQUIRED)
endif()

add_library(flexloop_tomlpp INTERFACE)
target_include_directories(flexloop_tomlpp SYSTEM INTERFACE ${TOMLPP_INCLUDE_DIR})
add_library(flexloop_cli11 INTERFACE)
target_include_directories(flexloop_cli11 SYSTEM INTERFACE ${CLI11_INCLUDE_DIR})
find_package(OpenSSL REQUIRED)  # SHA-256 of input files for provenance
# A controller FMU (controller/fmu): its zip archive and its modelDescription.xml.
# libzip by pkg-config: Debian 12's libzip CMake package refers to the zipcmp, zipmerge and
# ziptool programs, which libzip-dev does not install, and fails to load without them.
find_package(PkgConfig REQUIRED)
pkg_check_modules(LIBZIP REQUIRED IMPORTED_TARGET libzip>=1.7)
find_package(pugixml 1.13 REQUIRED CONFIG)
# Superelements (issue 58): Spectra (header-only Lanczos on Eigen) and CHOLMOD (SuiteSparse 5,
# no CMake package in Debian 12: found by name) for the sparse reduction.
find_package(Spectra 1.0 REQUIRED CONFIG PATHS /usr/share/spectra/cmake)
find_library(CHOLMOD_LIBRARY NAMES cholmod REQUIRED)
find_path(CHOLMOD_INCLUDE_DIR NAMES cholmod.h PATH_SUFFIXES suitesparse REQUIRED)
add_library(flexloop_cholmod INTERFACE)
target_include_directories(flexloop_cholmod SYSTEM INTERFACE ${CHOLMOD_INCLUDE_DIR})
target_link_libraries(flexloop_cholmod INTERFACE ${CHOLMOD_LIBRARY})
# NLopt (Debian 12: 2.7.1): the derivative-free bounded search of `flexloop campaign worst`.
find_package(NLopt 2.7 REQUIRED CONFIG)

# Eclipse iceoryx 2.0 (Debian 12: 2.0.3), the same-host shared-memory transport beside LCM (issue
# 48): the C++ API (posh, hoofs), the C binding for external controllers, and the iox-roudi daemon
# (package iceoryx) that owns the shared memory. Debian ships CMake packages for the libraries.
find_package(iceoryx_hoofs 2.0 REQUIRED CONFIG)
find_package(iceoryx_posh 2.0 REQUIRED CONFIG)
find_package(iceoryx_binding_c 2.0 REQUIRED CONFIG)
find_program(IOX_ROUDI_EXECUTABLE NAMES iox-roudi REQUIRED)
add_library(flexloop_iceoryx INTERFACE)
target_link_libraries(flexloop_iceoryx INTERFACE iceoryx_posh::iceoryx_posh
                      iceoryx_hoofs::iceoryx_hoofs)
get_target_property(_iceoryx_inc iceoryx_posh::iceoryx_posh INTERFACE_INCLUDE_DIRECTORIES)
target_include_directories(flexloop_iceoryx SYSTEM INTERFACE ${_iceoryx_inc})
