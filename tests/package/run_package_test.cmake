# Builds tests/package/consumer twice: against an install of micromacro in a temporary prefix
# (find_package), and embedding the source tree (add_subdirectory). Each build must run.
file(REMOVE_RECURSE ${WORK_DIR})
set(consumer ${SOURCE_DIR}/tests/package/consumer)

function(run)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "command failed (${rc}): ${ARGN}\n${out}\n${err}")
  endif()
endfunction()

# 1. install into a prefix, then find_package
run(${CMAKE_COMMAND} -S ${SOURCE_DIR} -B ${WORK_DIR}/lib -DCMAKE_CXX_COMPILER=${CXX_COMPILER}
    -DMICROMACRO_BUILD_TESTS=OFF -DMICROMACRO_BUILD_EXAMPLES=OFF)
run(${CMAKE_COMMAND} --install ${WORK_DIR}/lib --prefix ${WORK_DIR}/prefix)
run(${CMAKE_COMMAND} -S ${consumer} -B ${WORK_DIR}/found -DCMAKE_CXX_COMPILER=${CXX_COMPILER}
    -DCMAKE_PREFIX_PATH=${WORK_DIR}/prefix -DCMAKE_BUILD_TYPE=Release)
run(${CMAKE_COMMAND} --build ${WORK_DIR}/found)
run(${WORK_DIR}/found/app)

# 2. add_subdirectory
run(${CMAKE_COMMAND} -S ${consumer} -B ${WORK_DIR}/embedded -DCMAKE_CXX_COMPILER=${CXX_COMPILER}
    -DMICROMACRO_SOURCE_DIR=${SOURCE_DIR} -DCMAKE_BUILD_TYPE=Release)
run(${CMAKE_COMMAND} --build ${WORK_DIR}/embedded)
run(${WORK_DIR}/embedded/app)
message(STATUS "package test passed: find_package and add_subdirectory")
