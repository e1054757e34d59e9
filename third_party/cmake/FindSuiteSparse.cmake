# FindSuiteSparse: CHOLMOD (and its SuiteSparse dependencies) as the imported target
# SuiteSparse::CHOLMOD. Tries SuiteSparse's own CMake package first (SuiteSparse >= 7 ships one);
# Debian 12 ships 5.12 without it, so fall back to headers + libraries.
#
#   find_package(SuiteSparse REQUIRED COMPONENTS CHOLMOD)

find_package(CHOLMOD CONFIG QUIET)
if(TARGET SuiteSparse::CHOLMOD)
  set(SuiteSparse_FOUND TRUE)
  set(SuiteSparse_CHOLMOD_FOUND TRUE)
  return()
endif()

find_path(SuiteSparse_INCLUDE_DIR cholmod.h PATH_SUFFIXES suitesparse)
find_library(SuiteSparse_CHOLMOD_LIBRARY cholmod)
find_library(SuiteSparse_CONFIG_LIBRARY suitesparseconfig)
find_library(SuiteSparse_AMD_LIBRARY amd)
find_library(SuiteSparse_CAMD_LIBRARY camd)
find_library(SuiteSparse_COLAMD_LIBRARY colamd)
find_library(SuiteSparse_CCOLAMD_LIBRARY ccolamd)
find_package(BLAS QUIET)
find_package(LAPACK QUIET)

include(FindPackageHandleStandardArgs)
find_package_handle_standard_args(SuiteSparse
  REQUIRED_VARS SuiteSparse_INCLUDE_DIR SuiteSparse_CHOLMOD_LIBRARY SuiteSparse_CONFIG_LIBRARY
                SuiteSparse_AMD_LIBRARY SuiteSparse_COLAMD_LIBRARY)

if(SuiteSparse_FOUND AND NOT TARGET SuiteSparse::CHOLMOD)
  set(SuiteSparse_CHOLMOD_FOUND TRUE)
  add_library(SuiteSparse::CHOLMOD UNKNOWN IMPORTED)
  set(_deps ${SuiteSparse_AMD_LIBRARY} ${SuiteSparse_COLAMD_LIBRARY} ${SuiteSparse_CONFIG_LIBRARY})
  foreach(_opt SuiteSparse_CAMD_LIBRARY SuiteSparse_CCOLAMD_LIBRARY)
    if(${_opt})
      list(APPEND _deps ${${_opt}})
    endif()
  endforeach()
  if(LAPACK_FOUND)
    list(APPEND _deps ${LAPACK_LIBRARIES})
  endif()
  if(BLAS_FOUND)
    list(APPEND _deps ${BLAS_LIBRARIES})
  endif()
  set_target_properties(SuiteSparse::CHOLMOD PROPERTIES
    IMPORTED_LOCATION "${SuiteSparse_CHOLMOD_LIBRARY}"
    INTERFACE_INCLUDE_DIRECTORIES "${SuiteSparse_INCLUDE_DIR}"
    INTERFACE_LINK_LIBRARIES "${_deps}")
endif()
mark_as_advanced(SuiteSparse_INCLUDE_DIR SuiteSparse_CHOLMOD_LIBRARY SuiteSparse_CONFIG_LIBRARY
                 SuiteSparse_AMD_LIBRARY SuiteSparse_CAMD_LIBRARY SuiteSparse_COLAMD_LIBRARY
                 SuiteSparse_CCOLAMD_LIBRARY)
