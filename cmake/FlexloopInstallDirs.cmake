# SPDX-License-Identifier: BSD-3-Clause
# Where `cmake --install` puts things (doc/install.md), known before the subdirectories' own
# install() rules read them. GNUInstallDirs gives bin, lib (lib/<multiarch> for prefix /usr),
# include, share/man and share/doc/flexloop.
include(GNUInstallDirs)
set(FLEXLOOP_INSTALL_DATADIR ${CMAKE_INSTALL_DATADIR}/flexloop)
set(FLEXLOOP_INSTALL_EXAMPLESDIR ${FLEXLOOP_INSTALL_DATADIR}/examples)
set(FLEXLOOP_INSTALL_CMAKEDIR ${CMAKE_INSTALL_LIBDIR}/cmake/flexloop)
# Libraries flexloop loads itself (the plant FMU's, which `flexloop export-fmu` zips).
set(FLEXLOOP_INSTALL_PLUGINDIR ${CMAKE_INSTALL_LIBDIR}/flexloop)
# For the Python module that is to come (not built yet): where it is to go, as Debian's own.
set(FLEXLOOP_INSTALL_PYTHONDIR lib/python3/dist-packages CACHE STRING
    "Where the flexloop Python module installs (relative to the prefix)")
