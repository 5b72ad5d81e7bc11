# test_install: cmake --install into a scratch prefix, then build and run the
# consumers of tests/consumer against it:
#   - every public header has extern "C" guards;
#   - the installed libkin::kin links nothing but libkin.so (and libm);
#   - C with find_package: the shared library alone as on a machine without
#     the -dev packages the static library needs (their find modules
#     disabled), then shared and static (COMPONENTS static);
#   - C with pkg-config: shared with no other .pc file in sight, static
#     (libkin.a and `pkg-config --static --libs`);
#   - C++ (a project with only CXX enabled): shared and static;
#   - with -DFORTRAN=1 (libkin built with the Fortran module) a Fortran-only
#     project (no C enabled): shared alone with the -dev packages' find
#     modules disabled, then shared and static; and libkinf.pc.
# Arguments: -DSRC -DBIN -DWORK [-DFORTRAN].
file(REMOVE_RECURSE ${WORK})
set(PREFIX ${WORK}/prefix)

function(run)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "failed (${rc}): ${ARGN}\n${out}\n${err}")
  endif()
  message(STATUS "${out}")
endfunction()

run(${CMAKE_COMMAND} --install ${BIN} --prefix ${PREFIX})

# every installed header gives its declarations C linkage to C++ callers
file(GLOB_RECURSE headers ${PREFIX}/include/*.h)
list(LENGTH headers nheaders)
if(nheaders LESS 2)
  message(FATAL_ERROR "no headers installed under ${PREFIX}/include")
endif()
foreach(h ${headers})
  file(READ ${h} text)
  if(NOT text MATCHES "#ifdef __cplusplus\nextern \"C\" {\n#endif" OR NOT text MATCHES "#ifdef __cplusplus\n}\n#endif")
    message(FATAL_ERROR "${h}: no extern \"C\" guard (#ifdef __cplusplus / extern \"C\" { ... })")
  endif()
endforeach()

# the shared library's installed target names none of the static library's
# dependencies, and no path of the machine libkin was built on
file(GLOB shared_targets ${PREFIX}/lib*/cmake/libkin/libkinTargets.cmake)
file(STRINGS ${shared_targets} link_lines REGEX "INTERFACE_LINK_LIBRARIES")
if(link_lines MATCHES "LAPACK|GSL|Threads|JANSSON|NAUTY|kin_klu|/")
  message(FATAL_ERROR "libkin::kin links more than libkin.so: ${link_lines}")
endif()

file(GLOB libdirs ${PREFIX}/lib*)
string(REPLACE ";" ":" ldpath "${libdirs}")
file(GLOB libkin_a ${PREFIX}/lib*/libkin.a)
file(GLOB pcdir ${PREFIX}/lib*/pkgconfig)

# Standing in for a machine with libkin's runtime packages but not the -dev
# packages only the static library needs: their find modules are disabled
# (find_package fails), so the shared consumer must not look for them.
set(no_dev_packages
  -DCMAKE_DISABLE_FIND_PACKAGE_LAPACK=ON -DCMAKE_DISABLE_FIND_PACKAGE_BLAS=ON
  -DCMAKE_DISABLE_FIND_PACKAGE_GSL=ON -DCMAKE_DISABLE_FIND_PACKAGE_PkgConfig=ON
  -DCMAKE_DISABLE_FIND_PACKAGE_Threads=ON)

# find_package consumers (C)
run(${CMAKE_COMMAND} -S ${SRC}/tests/consumer -B ${WORK}/cmake-consumer-shared
    -DCMAKE_PREFIX_PATH=${PREFIX} -DWITH_STATIC=OFF ${no_dev_packages})
run(${CMAKE_COMMAND} --build ${WORK}/cmake-consumer-shared)
run(${CMAKE_COMMAND} -E env LD_LIBRARY_PATH=${ldpath} ${WORK}/cmake-consumer-shared/consumer)
run(${CMAKE_COMMAND} -S ${SRC}/tests/consumer -B ${WORK}/cmake-consumer -DCMAKE_PREFIX_PATH=${PREFIX})
run(${CMAKE_COMMAND} --build ${WORK}/cmake-consumer)
run(${CMAKE_COMMAND} -E env LD_LIBRARY_PATH=${ldpath} ${WORK}/cmake-consumer/consumer)
run(${WORK}/cmake-consumer/consumer_static)

# pkg-config consumers (C)
find_program(PKG_CONFIG pkg-config REQUIRED)
find_program(CC NAMES cc gcc clang REQUIRED)
function(pkgconfig var env)
  execute_process(COMMAND ${CMAKE_COMMAND} -E env ${env} ${PKG_CONFIG} ${ARGN}
    OUTPUT_VARIABLE flags ERROR_VARIABLE err RESULT_VARIABLE rc OUTPUT_STRIP_TRAILING_WHITESPACE)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "pkg-config ${ARGN} (${env}) failed:\n${err}")
  endif()
  separate_arguments(flags UNIX_COMMAND "${flags}")
  set(${var} ${flags} PARENT_SCOPE)
endfunction()
# shared: only libkin's own .pc files in sight (no gsl.pc, jansson.pc, nauty.pc)
pkgconfig(flags PKG_CONFIG_LIBDIR=${pcdir} --cflags --libs libkin)
run(${CC} -std=c99 ${SRC}/tests/consumer/main.c -o ${WORK}/pc-consumer ${flags})
run(${CMAKE_COMMAND} -E env LD_LIBRARY_PATH=${ldpath} ${WORK}/pc-consumer)
# static: libkin.a with what `pkg-config --static` says it needs
pkgconfig(flags PKG_CONFIG_PATH=${pcdir} --static --cflags --libs libkin)
list(TRANSFORM flags REPLACE "^-lkin$" "${libkin_a}")
run(${CC} -std=c99 ${SRC}/tests/consumer/main.c -o ${WORK}/pc-consumer-static ${flags})
run(${WORK}/pc-consumer-static)

# C++ consumer: a project with only CXX enabled
run(${CMAKE_COMMAND} -S ${SRC}/tests/consumer/cpp -B ${WORK}/cpp-consumer -DCMAKE_PREFIX_PATH=${PREFIX})
run(${CMAKE_COMMAND} --build ${WORK}/cpp-consumer)
run(${CMAKE_COMMAND} -E env LD_LIBRARY_PATH=${ldpath} ${WORK}/cpp-consumer/consumer_cpp)
run(${WORK}/cpp-consumer/consumer_cpp_static)
message(STATUS "test_install: C++ consumers (shared, static) passed")

# Fortran consumers: a Fortran-only project, find_package(libkin COMPONENTS
# Fortran), module libkin; and libkinf.pc
if(FORTRAN)
  run(${CMAKE_COMMAND} -S ${SRC}/tests/consumer/fortran -B ${WORK}/fortran-consumer-shared
      -DCMAKE_PREFIX_PATH=${PREFIX} -DWITH_STATIC=OFF ${no_dev_packages})
  run(${CMAKE_COMMAND} --build ${WORK}/fortran-consumer-shared)
  run(${CMAKE_COMMAND} -E env LD_LIBRARY_PATH=${ldpath} ${WORK}/fortran-consumer-shared/consumer_fortran)
  run(${CMAKE_COMMAND} -S ${SRC}/tests/consumer/fortran -B ${WORK}/fortran-consumer
      -DCMAKE_PREFIX_PATH=${PREFIX})
  run(${CMAKE_COMMAND} --build ${WORK}/fortran-consumer)
  run(${CMAKE_COMMAND} -E env LD_LIBRARY_PATH=${ldpath} ${WORK}/fortran-consumer/consumer_fortran)
  run(${WORK}/fortran-consumer/consumer_fortran_static)
  find_program(FC NAMES gfortran REQUIRED)
  pkgconfig(flags PKG_CONFIG_LIBDIR=${pcdir} --cflags --libs libkinf)
  run(${FC} ${SRC}/tests/consumer/fortran/main.f90 -o ${WORK}/pc-consumer-fortran ${flags})
  run(${CMAKE_COMMAND} -E env LD_LIBRARY_PATH=${ldpath} ${WORK}/pc-consumer-fortran)
  message(STATUS "test_install: Fortran-only consumers (shared, static, libkinf.pc) passed")
endif()
message(STATUS "test_install: find_package (shared alone, shared and static) and pkg-config consumers passed")
