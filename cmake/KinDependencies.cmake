# The libraries found without a CMake package of their own, for the library
# (CMakeLists.txt) and the fuzz project (tests/fuzz/CMakeLists.txt), which
# compiles the same sources: jansson and nauty by pkg-config, SuiteSparse KLU
# by its headers and libraries. Defines PkgConfig::JANSSON, PkgConfig::NAUTY,
# KIN_KLU_INCLUDE_DIR, KIN_KLU_LIBRARIES and the target kin_klu.
find_package(PkgConfig REQUIRED)
# jansson reads and writes the JSON model files (libkin/io/model_io.c).
pkg_check_modules(JANSSON REQUIRED IMPORTED_TARGET jansson)
# nauty's Traces: the automorphisms of the bar graph (libkin/symmetry/symmetry_graph.c).
pkg_check_modules(NAUTY REQUIRED IMPORTED_TARGET nauty)
# SuiteSparse KLU: the sparse LU of KIN_STEP_SPARSE (libkin/path/sparse.c).
# Debian's libsuitesparse-dev has no CMake package: headers and libraries
# are found directly (klu needs amd, colamd, btf and suitesparseconfig;
# cholmod gives the METIS nested-dissection column order).
find_path(KIN_KLU_INCLUDE_DIR klu.h PATH_SUFFIXES suitesparse REQUIRED)
set(KIN_KLU_LIBRARIES)
foreach(_ss klu cholmod amd colamd btf suitesparseconfig)
  find_library(KIN_SS_${_ss} ${_ss} REQUIRED)
  list(APPEND KIN_KLU_LIBRARIES ${KIN_SS_${_ss}})
endforeach()
if(NOT TARGET kin_klu)
  add_library(kin_klu INTERFACE IMPORTED)
  set_target_properties(kin_klu PROPERTIES
    INTERFACE_INCLUDE_DIRECTORIES "${KIN_KLU_INCLUDE_DIR}"
    INTERFACE_LINK_LIBRARIES "${KIN_KLU_LIBRARIES}")
endif()
# Arb (Debian 12's libflint-arb-dev: library flint-arb, headers arb.h, acb.h
# in the include path) on FLINT: the ball arithmetic of the interval
# certificates of the complete solver (libkin/homotopy/certify/) and of the
# located bifurcations. Defines KIN_ARB_INCLUDE_DIR, KIN_ARB_LIBRARIES and the
# target kin_arb.
find_path(KIN_ARB_INCLUDE_DIR acb_mat.h PATH_SUFFIXES arb flint REQUIRED)
find_library(KIN_ARB_LIB NAMES flint-arb arb REQUIRED)
find_library(KIN_FLINT_LIB flint REQUIRED)
# GMP: FLINT's fmpz inlines call it (certify/homotopy_prove_fast.c)
find_library(KIN_GMP_LIB gmp REQUIRED)
set(KIN_ARB_LIBRARIES ${KIN_ARB_LIB} ${KIN_FLINT_LIB} ${KIN_GMP_LIB})
if(NOT TARGET kin_arb)
  add_library(kin_arb INTERFACE IMPORTED)
  set_target_properties(kin_arb PROPERTIES
    INTERFACE_INCLUDE_DIRECTORIES "${KIN_ARB_INCLUDE_DIR}"
    INTERFACE_LINK_LIBRARIES "${KIN_ARB_LIBRARIES}")
endif()
