# Finds the third-party stack from Debian packages. Every failure names the package to install.

macro(colibri_require_header var header pkg)
  find_path(${var} NAMES ${header})
  if(NOT ${var})
    message(FATAL_ERROR "Colibri: header <${header}> not found; install the Debian package ${pkg} "
                        "(apt-get install ${pkg}, or run scripts/setup)")
  endif()
endmacro()

macro(colibri_require_library var name pkg)
  find_library(${var} NAMES ${name})
  if(NOT ${var})
    message(FATAL_ERROR "Colibri: library ${name} not found; install the Debian package ${pkg} "
                        "(apt-get install ${pkg}, or run scripts/setup)")
  endif()
endmacro()

colibri_require_header(GMP_INCLUDE_DIR gmp.h libgmp-dev)
colibri_require_library(GMP_LIBRARY gmp libgmp-dev)
colibri_require_header(MPFR_INCLUDE_DIR mpfr.h libmpfr-dev)
colibri_require_library(MPFR_LIBRARY mpfr libmpfr-dev)
colibri_require_header(FLINT_INCLUDE_DIR flint/flint.h libflint-dev)
colibri_require_library(FLINT_LIBRARY flint libflint-dev)
colibri_require_header(ARB_INCLUDE_DIR arb_fmpz_poly.h libflint-arb-dev)
colibri_require_library(ARB_LIBRARY flint-arb libflint-arb-dev)

add_library(colibri_flint INTERFACE)
target_include_directories(colibri_flint SYSTEM INTERFACE
  ${FLINT_INCLUDE_DIR} ${ARB_INCLUDE_DIR} ${MPFR_INCLUDE_DIR} ${GMP_INCLUDE_DIR})
target_link_libraries(colibri_flint INTERFACE
  ${ARB_LIBRARY} ${FLINT_LIBRARY} ${MPFR_LIBRARY} ${GMP_LIBRARY})

find_package(TBB CONFIG QUIET)
if(NOT TBB_FOUND)
  message(FATAL_ERROR "Colibri: oneTBB not found; install the Debian package libtbb-dev")
endif()
find_package(OpenMesh CONFIG QUIET)
if(NOT OpenMesh_FOUND)
  message(FATAL_ERROR "Colibri: OpenMesh not found; install the Debian package libopenmesh-dev")
endif()
find_package(CGAL CONFIG QUIET)
if(NOT CGAL_FOUND)
  message(FATAL_ERROR "Colibri: CGAL not found; install the Debian package libcgal-dev")
endif()

find_library(MATH_LIBRARY m)
