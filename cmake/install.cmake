# What `cmake --install` puts where, and the DEB package (scripts/package.sh runs cpack).
#
# Component "runtime", the default install and the whole DEB: the tool.
#   bin/tubecast                    (cli/CMakeLists.txt)
#   share/tubecast/configs/         the example scenes; configs/demo.json generates its dataset
#   share/doc/tubecast/             README.md, docs/*.md
# The binary needs nothing else at run time: shaders are embedded (shaders/CMakeLists.txt) and
# the demo's dataset is generated.
#
# Component "dev", only on request (`cmake --install build --component dev`), never in the DEB:
# the static libraries, their headers under include/tubecast/ and a CMake package exporting
# tubecast::core, tubecast::io, tubecast::gl, tubecast::rt, tubecast::cli (tubecast::shaders is
# the embedded shader sources of gl). Headers are installed so that the export is complete and
# find_package(tubecast) works from an install (tests/package checks it); they are not packaged
# because the library API is internal to the tool and changes with it.

install(DIRECTORY ${PROJECT_SOURCE_DIR}/configs/ DESTINATION ${CMAKE_INSTALL_DATADIR}/tubecast/configs
        COMPONENT runtime)
file(GLOB TUBECAST_DOCS CONFIGURE_DEPENDS ${PROJECT_SOURCE_DIR}/docs/*.md)
install(FILES ${PROJECT_SOURCE_DIR}/README.md ${TUBECAST_DOCS} DESTINATION ${CMAKE_INSTALL_DOCDIR}
        COMPONENT runtime)
if(EXISTS ${PROJECT_SOURCE_DIR}/LICENSE)
  install(FILES ${PROJECT_SOURCE_DIR}/LICENSE DESTINATION ${CMAKE_INSTALL_DOCDIR} COMPONENT runtime)
endif()

set(TUBECAST_CMAKE_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/tubecast)
install(TARGETS tubecast_core tubecast_io tubecast_gl tubecast_rt tubecast_shaders tubecast_cli
        EXPORT tubecastTargets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR} COMPONENT dev EXCLUDE_FROM_ALL
        FILE_SET HEADERS DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/tubecast COMPONENT dev EXCLUDE_FROM_ALL
        FILE_SET generated DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/tubecast COMPONENT dev EXCLUDE_FROM_ALL)
install(EXPORT tubecastTargets NAMESPACE tubecast:: DESTINATION ${TUBECAST_CMAKE_DIR}
        COMPONENT dev EXCLUDE_FROM_ALL)
include(CMakePackageConfigHelpers)
configure_package_config_file(${CMAKE_CURRENT_LIST_DIR}/tubecastConfig.cmake.in
                              ${CMAKE_CURRENT_BINARY_DIR}/tubecastConfig.cmake
                              INSTALL_DESTINATION ${TUBECAST_CMAKE_DIR})
write_basic_package_version_file(${CMAKE_CURRENT_BINARY_DIR}/tubecastConfigVersion.cmake
                                 COMPATIBILITY SameMinorVersion)
install(FILES ${CMAKE_CURRENT_BINARY_DIR}/tubecastConfig.cmake ${CMAKE_CURRENT_BINARY_DIR}/tubecastConfigVersion.cmake
              ${CMAKE_CURRENT_LIST_DIR}/FindIceT.cmake
        DESTINATION ${TUBECAST_CMAKE_DIR} COMPONENT dev EXCLUDE_FROM_ALL)

# DEB: tubecast_<version>_amd64.deb with the runtime component only. Dependencies: the packages
# that provide the shared libraries the binary links, found by dpkg-shlibdeps from the local dpkg
# database (offline; dpkg-dev), plus what is loaded at run time without being linked: Mesa's EGL
# implementation behind libglvnd's libEGL, and the DRI drivers (llvmpipe) that EGL and OSMesa load.
set(CPACK_GENERATOR DEB)
set(CPACK_PACKAGE_NAME tubecast)
set(CPACK_PACKAGE_VERSION ${PROJECT_VERSION})
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY "headless batch renderer for dense 3D line sets and particles")
set(CPACK_PACKAGE_DESCRIPTION "\
tubecast renders streamlines, fiber tracts and particles from a dataset and a
JSON scene to PNG/EXR frames with depth, normal and id AOVs and timing CSVs,
without a window or display: OpenGL 4.5 offscreen through EGL or OSMesa (Mesa
llvmpipe on machines without a GPU), or Embree ray tracing on the CPU.
Example scenes are in /usr/share/tubecast/configs.")
set(CPACK_PACKAGE_CONTACT "tubecast maintainers" CACHE STRING "Maintainer field of the DEB")
set(CPACK_INSTALL_CMAKE_PROJECTS "${CMAKE_BINARY_DIR};tubecast;runtime;/")
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_SECTION graphics)
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
set(CPACK_DEBIAN_PACKAGE_DEPENDS "libegl-mesa0, libgl1-mesa-dri")
# Programs and files loaded by path at run time by optional features, each failing with a message
# that names the package when absent: ffmpeg (`tubecast encode`, output.video) and DejaVu Sans
# (the default font of overlay text, overlay.font).
set(CPACK_DEBIAN_PACKAGE_RECOMMENDS "ffmpeg, fonts-dejavu-core")
include(CPack)
