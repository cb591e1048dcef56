# FindCHOLMOD: SuiteSparse 5.x (Debian 12) installs no CMake package for CHOLMOD, so this
# module locates the header and the libraries CHOLMOD links against and defines
#   SuiteSparse::CHOLMOD  (imported target: cholmod, amd, camd, colamd, ccolamd,
#                          suitesparseconfig, LAPACK, BLAS)
#   SuiteSparse::SPQR     (imported target: spqr on top of CHOLMOD)
#   CHOLMOD_FOUND, CHOLMOD_INCLUDE_DIR, CHOLMOD_VERSION
include(FindPackageHandleStandardArgs)

find_path(CHOLMOD_INCLUDE_DIR cholmod.h PATH_SUFFIXES suitesparse)
foreach(lib cholmod amd camd colamd ccolamd suitesparseconfig spqr)
  string(TOUPPER ${lib} LIB)
  find_library(${LIB}_LIBRARY NAMES ${lib})
endforeach()

if(CHOLMOD_INCLUDE_DIR AND EXISTS "${CHOLMOD_INCLUDE_DIR}/cholmod_core.h")
  file(STRINGS "${CHOLMOD_INCLUDE_DIR}/cholmod_core.h" _ver REGEX "#define CHOLMOD_(MAIN|SUB)_VERSION")
  string(REGEX REPLACE ".*MAIN_VERSION[ \t]+([0-9]+).*" "\\1" _major "${_ver}")
  string(REGEX REPLACE ".*SUB_VERSION[ \t]+([0-9]+).*" "\\1" _minor "${_ver}")
  set(CHOLMOD_VERSION "${_major}.${_minor}")
endif()

find_package(LAPACK QUIET)
find_package(BLAS QUIET)

find_package_handle_standard_args(CHOLMOD
  REQUIRED_VARS CHOLMOD_INCLUDE_DIR CHOLMOD_LIBRARY AMD_LIBRARY CAMD_LIBRARY COLAMD_LIBRARY
                CCOLAMD_LIBRARY SUITESPARSECONFIG_LIBRARY LAPACK_FOUND BLAS_FOUND
  VERSION_VAR CHOLMOD_VERSION)

if(CHOLMOD_FOUND AND NOT TARGET SuiteSparse::CHOLMOD)
  add_library(SuiteSparse::CHOLMOD UNKNOWN IMPORTED)
  set_target_properties(SuiteSparse::CHOLMOD PROPERTIES
    IMPORTED_LOCATION "${CHOLMOD_LIBRARY}"
    INTERFACE_INCLUDE_DIRECTORIES "${CHOLMOD_INCLUDE_DIR}"
    INTERFACE_LINK_LIBRARIES
      "${AMD_LIBRARY};${CAMD_LIBRARY};${COLAMD_LIBRARY};${CCOLAMD_LIBRARY};${SUITESPARSECONFIG_LIBRARY};${LAPACK_LIBRARIES};${BLAS_LIBRARIES}")
  if(SPQR_LIBRARY)
    add_library(SuiteSparse::SPQR UNKNOWN IMPORTED)
    set_target_properties(SuiteSparse::SPQR PROPERTIES
      IMPORTED_LOCATION "${SPQR_LIBRARY}"
      INTERFACE_LINK_LIBRARIES SuiteSparse::CHOLMOD)
  endif()
endif()
mark_as_advanced(CHOLMOD_INCLUDE_DIR CHOLMOD_LIBRARY AMD_LIBRARY CAMD_LIBRARY COLAMD_LIBRARY
                 CCOLAMD_LIBRARY SUITESPARSECONFIG_LIBRARY SPQR_LIBRARY)
