# FindIceT: the IceT sort-last image compositing library (Sandia), as ParaView ships it.
#
# Debian has no IceT package of its own: IceT 2.x is built inside ParaView, its libraries
# (libvtkIceTCore-pv<ver>, libvtkIceTMPI-pv<ver>) come with the `paraview` package and its headers
# (IceT.h, IceTMPI.h, IceTConfig.h under <prefix>/include/paraview-<ver>/vtkicet/src/include) with
# `paraview-dev`. A stand-alone IceT install (libIceTCore, libIceTMPI, include/IceT.h) is found too.
#
# ParaView's own CMake package exports these targets (ParaView::icet) but cannot be used here: it
# loads every ParaView module, its bundled VTK build among them, and fails on Debian when the
# Python modules it references (python3-paraview) are not installed.
#
# Result:
#   IceT::IceT        imported target: IceTMPI + IceTCore, include directory, MPI::MPI_C
#   IceT_FOUND, IceT_VERSION (from IceTConfig.h), IceT_INCLUDE_DIR, IceT_CORE_LIBRARY, IceT_MPI_LIBRARY
# Hints: IceT_ROOT, or the cache variables above.

include(FindPackageHandleStandardArgs)

# ParaView's versioned install locations, newest first; the header directory names the version.
file(GLOB _icet_pv_includes LIST_DIRECTORIES true
     /usr/include/paraview-*/vtkicet/src/include /usr/local/include/paraview-*/vtkicet/src/include)
list(SORT _icet_pv_includes COMPARE NATURAL ORDER DESCENDING)
set(_icet_pv_suffixes "")
foreach(_dir IN LISTS _icet_pv_includes)
  string(REGEX MATCH "paraview-([0-9]+\\.[0-9]+)" _m "${_dir}")
  list(APPEND _icet_pv_suffixes "-pv${CMAKE_MATCH_1}")
endforeach()

find_path(IceT_INCLUDE_DIR NAMES IceT.h IceTMPI.h HINTS ${_icet_pv_includes} PATH_SUFFIXES include
          DOC "Directory of IceT.h and IceTMPI.h")

set(_icet_core_names IceTCore)
set(_icet_mpi_names IceTMPI)
foreach(_suffix IN LISTS _icet_pv_suffixes)
  list(APPEND _icet_core_names vtkIceTCore${_suffix})
  list(APPEND _icet_mpi_names vtkIceTMPI${_suffix})
endforeach()
find_library(IceT_CORE_LIBRARY NAMES ${_icet_core_names} DOC "IceT core library")
find_library(IceT_MPI_LIBRARY NAMES ${_icet_mpi_names} DOC "IceT MPI communicator library")

if(IceT_INCLUDE_DIR AND EXISTS "${IceT_INCLUDE_DIR}/IceTConfig.h")
  file(STRINGS "${IceT_INCLUDE_DIR}/IceTConfig.h" _icet_version_line REGEX "#define ICET_VERSION[ \t]+\"")
  string(REGEX REPLACE ".*\"([^\"]+)\".*" "\\1" IceT_VERSION "${_icet_version_line}")
endif()

find_package_handle_standard_args(IceT REQUIRED_VARS IceT_MPI_LIBRARY IceT_CORE_LIBRARY IceT_INCLUDE_DIR
                                  VERSION_VAR IceT_VERSION)

if(IceT_FOUND AND NOT TARGET IceT::IceT)
  # IceTMPI.h includes mpi.h: the MPI C target comes with the IceT target.
  if(NOT TARGET MPI::MPI_C)
    find_package(MPI REQUIRED COMPONENTS C)
  endif()
  add_library(IceT::Core UNKNOWN IMPORTED)
  set_target_properties(IceT::Core PROPERTIES IMPORTED_LOCATION "${IceT_CORE_LIBRARY}"
                        INTERFACE_INCLUDE_DIRECTORIES "${IceT_INCLUDE_DIR}")
  add_library(IceT::MPI UNKNOWN IMPORTED)
  set_target_properties(IceT::MPI PROPERTIES IMPORTED_LOCATION "${IceT_MPI_LIBRARY}"
                        INTERFACE_LINK_LIBRARIES "IceT::Core;MPI::MPI_C")
  add_library(IceT::IceT INTERFACE IMPORTED)
  set_target_properties(IceT::IceT PROPERTIES INTERFACE_LINK_LIBRARIES IceT::MPI)
endif()

mark_as_advanced(IceT_INCLUDE_DIR IceT_CORE_LIBRARY IceT_MPI_LIBRARY)
unset(_icet_pv_includes)
unset(_icet_pv_suffixes)
unset(_icet_core_names)
unset(_icet_mpi_names)
