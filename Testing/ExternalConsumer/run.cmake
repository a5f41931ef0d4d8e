# SPDX-License-Identifier: BSD-3-Clause
# ctest driver: install this build into a fresh prefix, then configure, build and run the
# external consumer against it. Variables: BUILD_DIR, SOURCE_DIR, WORK_DIR, MESH.
file(REMOVE_RECURSE "${WORK_DIR}")
function (run)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE result OUTPUT_VARIABLE output ERROR_VARIABLE output)
  if (NOT result EQUAL 0)
    message(FATAL_ERROR "failed (${result}): ${ARGN}\n${output}")
  endif ()
  message(STATUS "${output}")
endfunction ()
run("${CMAKE_COMMAND}" --install "${BUILD_DIR}" --prefix "${WORK_DIR}/prefix")
run("${CMAKE_COMMAND}" -S "${SOURCE_DIR}" -B "${WORK_DIR}/build" -DCMAKE_BUILD_TYPE=Release
  "-DCMAKE_PREFIX_PATH=${WORK_DIR}/prefix")
run("${CMAKE_COMMAND}" --build "${WORK_DIR}/build")
run("${WORK_DIR}/build/consumer" "${MESH}")
