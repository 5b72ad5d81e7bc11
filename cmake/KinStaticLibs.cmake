# KIN_PC_LIBS_PRIVATE: the -l flags of libkin.pc's Libs.private, i.e. what
# `cc -static app.c $(pkg-config --static --libs libkin)` needs after -lkin,
# derived from the libraries found here rather than written for one machine:
#   - GSL, LAPACK/BLAS, jansson, nauty: their own .pc files' static libraries
#     (pkg-config --static), the found library's name when there is none;
#   - SuiteSparse (no .pc before 7.x): what the found shared libraries name
#     in their DT_NEEDED entries (readelf): KLU's amd, colamd, btf,
#     suitesparseconfig; CHOLMOD's ccolamd, camd, METIS, OpenMP (gomp);
#   - the compiler's runtimes those bring in (gfortran -> quadmath): the
#     DT_NEEDED entries of the compiler's own libgfortran.so, libgomp.so;
#   - threads, dl, libm.
# Listed in link order (a library before the ones it needs; on a repeat the
# last place is kept). As libraries rather than Requires.private: pkg-config
# resolves Requires.private also for a shared consumer's --cflags, which
# would then need gsl.pc, jansson.pc and nauty.pc (their -dev packages).

# lib<name>.so[.N] -> <name>; the C library, the dynamic loader and libgcc_s
# (no static archive; -static links libgcc.a/libgcc_eh.a instead) left out,
# and a library the compiler cannot link by name (neither lib<name>.a nor
# lib<name>.so: Debian's libmetis5 without libmetis-dev) left out too, as it
# would break the ordinary link of libkin.a against shared libraries; it is
# recorded in KIN_STATIC_MISSING instead (a fully static link cannot work).
set(KIN_STATIC_MISSING)
function(_kin_needed lib out)
  set(names)
  set(missing ${KIN_STATIC_MISSING})
  if(CMAKE_READELF AND EXISTS "${lib}" AND lib MATCHES "\\.so")
    execute_process(COMMAND ${CMAKE_READELF} -d ${lib} OUTPUT_VARIABLE dyn ERROR_QUIET)
    string(REGEX MATCHALL "Shared library: \\[lib[^]]+\\]" needed "${dyn}")
    foreach(n IN LISTS needed)
      string(REGEX REPLACE "Shared library: \\[lib(.+)\\.so.*" "\\1" n "${n}")
      if(n MATCHES "^(c|gcc_s)$")
        continue()
      endif()
      set(found FALSE)
      foreach(ext a so)
        execute_process(COMMAND ${CMAKE_C_COMPILER} -print-file-name=lib${n}.${ext}
          OUTPUT_VARIABLE p OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET)
        if(IS_ABSOLUTE "${p}" AND EXISTS "${p}")
          set(found TRUE)
        endif()
      endforeach()
      if(found)
        list(APPEND names ${n})
      else()
        list(APPEND missing ${n})
      endif()
    endforeach()
  endif()
  list(REMOVE_DUPLICATES missing)
  set(KIN_STATIC_MISSING ${missing} PARENT_SCOPE)
  set(${out} ${names} PARENT_SCOPE)
endfunction()

# a found library (path or name) -> its pkg-config module's static libraries
# when one has the library's name, else the name itself
function(_kin_pc_or_name lib out)
  get_filename_component(n "${lib}" NAME)
  string(REGEX REPLACE "^lib" "" n "${n}")
  string(REGEX REPLACE "\\.(so|a|dylib|tbd)(\\..*)?$" "" n "${n}")
  string(MAKE_C_IDENTIFIER "_KIN_PC_${n}" v)
  pkg_check_modules(${v} QUIET ${n})
  if(${v}_FOUND AND ${v}_STATIC_LIBRARIES)
    set(${out} ${${v}_STATIC_LIBRARIES} PARENT_SCOPE)
  else()
    set(${out} ${n} PARENT_SCOPE)
  endif()
endfunction()

set(_kin_static)
# GSL: gsl.pc says -lgsl -lgslcblas -lm (FindGSL's GSL_LIBRARIES, without it)
_kin_pc_or_name(gsl _l)
if(_l STREQUAL "gsl")
  set(_l gsl gslcblas m)
endif()
list(APPEND _kin_static ${_l})
list(APPEND _kin_static ${JANSSON_STATIC_LIBRARIES} ${NAUTY_STATIC_LIBRARIES})
# Arb and FLINT (no .pc in Debian 12): by name, then what FLINT needs
list(APPEND _kin_static flint-arb flint mpfr gmp)

# SuiteSparse: the libraries libkin names, then the SuiteSparse ones they
# need, in dependency order, then the others they need (METIS, OpenMP, ...)
set(_kin_ss_order klu cholmod ccolamd camd amd colamd btf suitesparseconfig)
set(_kin_ss_needed)
foreach(_ss klu cholmod amd colamd btf suitesparseconfig)
  _kin_needed("${KIN_SS_${_ss}}" _l)
  list(APPEND _kin_ss_needed ${_ss} ${_l})
endforeach()
set(_kin_ss_other ${_kin_ss_needed})
foreach(_ss IN LISTS _kin_ss_order)
  if(_ss IN_LIST _kin_ss_needed)
    list(APPEND _kin_static ${_ss})
  endif()
  list(REMOVE_ITEM _kin_ss_other ${_ss})
endforeach()
list(APPEND _kin_static ${_kin_ss_other})

# LAPACK and BLAS (lapack.pc: -llapack -lgfortran -lpthread -lm on Debian)
foreach(_lib IN LISTS LAPACK_LIBRARIES)
  if(_lib MATCHES "^-" OR _lib MATCHES "Threads::|^(m|pthread|dl)$")
    continue()
  endif()
  _kin_pc_or_name("${_lib}" _l)
  list(APPEND _kin_static ${_l})
endforeach()

# the compiler's runtimes brought in above: their own dependencies
foreach(_rt gfortran gomp)
  if(_rt IN_LIST _kin_static)
    execute_process(COMMAND ${CMAKE_C_COMPILER} -print-file-name=lib${_rt}.so
      OUTPUT_VARIABLE _so OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET)
    _kin_needed("${_so}" _l)
    list(APPEND _kin_static ${_l})
  endif()
endforeach()

# threads, dlopen (libkin/linalg/blas_threads.c), libm
string(REGEX REPLACE "^-l" "" _l "${CMAKE_THREAD_LIBS_INIT}")
if(_l STREQUAL "-pthread" OR _l STREQUAL "")
  set(_l pthread)
endif()
list(APPEND _kin_static ${_l} ${CMAKE_DL_LIBS} m)

# a repeat keeps its last place (after everything that needs it)
list(REVERSE _kin_static)
list(REMOVE_DUPLICATES _kin_static)
list(REVERSE _kin_static)
list(TRANSFORM _kin_static PREPEND "-l")
string(REPLACE ";" " " KIN_PC_LIBS_PRIVATE "${_kin_static}")
message(STATUS "libkin: static link (libkin.pc Libs.private) ${KIN_PC_LIBS_PRIVATE}")
if(KIN_STATIC_MISSING)
  message(STATUS "libkin: no library to link for ${KIN_STATIC_MISSING}: a fully static link (cc -static) will not work")
endif()
