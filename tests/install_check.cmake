# test_install: cmake --install into a scratch prefix, then build and run a
# consumer with find_package(libkin) (shared and static) and one with
# pkg-config; with -DFORTRAN=1 (libkin built with the Fortran module) also
# a Fortran consumer (shared and static). Arguments: -DSRC -DBIN -DWORK
# [-DFORTRAN].
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

# find_package consumer
run(${CMAKE_COMMAND} -S ${SRC}/tests/consumer -B ${WORK}/cmake-consumer -DCMAKE_PREFIX_PATH=${PREFIX})
run(${CMAKE_COMMAND} --build ${WORK}/cmake-consumer)
file(GLOB libdirs ${PREFIX}/lib*)
string(REPLACE ";" ":" ldpath "${libdirs}")
run(${CMAKE_COMMAND} -E env LD_LIBRARY_PATH=${ldpath} ${WORK}/cmake-consumer/consumer)
run(${WORK}/cmake-consumer/consumer_static)

# pkg-config consumer
find_program(PKG_CONFIG pkg-config REQUIRED)
find_program(CC NAMES cc gcc clang REQUIRED)
file(GLOB pcdir ${PREFIX}/lib*/pkgconfig)
execute_process(COMMAND ${CMAKE_COMMAND} -E env PKG_CONFIG_PATH=${pcdir} ${PKG_CONFIG} --cflags --libs libkin
  OUTPUT_VARIABLE flags RESULT_VARIABLE rc OUTPUT_STRIP_TRAILING_WHITESPACE)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "pkg-config --cflags --libs libkin failed")
endif()
separate_arguments(flags UNIX_COMMAND "${flags}")
run(${CC} -std=c99 ${SRC}/tests/consumer/main.c -o ${WORK}/pc-consumer ${flags})
run(${CMAKE_COMMAND} -E env LD_LIBRARY_PATH=${ldpath} ${WORK}/pc-consumer)

# Fortran consumer: find_package(libkin COMPONENTS Fortran), module libkin
if(FORTRAN)
  run(${CMAKE_COMMAND} -S ${SRC}/tests/consumer/fortran -B ${WORK}/fortran-consumer
      -DCMAKE_PREFIX_PATH=${PREFIX})
  run(${CMAKE_COMMAND} --build ${WORK}/fortran-consumer)
  run(${CMAKE_COMMAND} -E env LD_LIBRARY_PATH=${ldpath} ${WORK}/fortran-consumer/consumer_fortran)
  run(${WORK}/fortran-consumer/consumer_fortran_static)
  message(STATUS "test_install: Fortran consumers (shared, static) passed")
endif()
message(STATUS "test_install: find_package (shared, static) and pkg-config consumers passed")
