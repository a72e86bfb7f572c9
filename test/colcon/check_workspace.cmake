# Builds a colcon workspace holding this package and test/colcon's consumer package,
# as a ROS user would, then runs the consumer from the workspace's install space.
# Arguments: SOURCE_DIR (this project), WORK_DIR (the workspace, emptied first),
# COLCON (the colcon executable, or empty), LAUNCHER (a compiler launcher, optional).
if(NOT COLCON)
  # CI must prove the workspace builds; elsewhere the test is reported as skipped
  # (SKIP_REGULAR_EXPRESSION in test/CMakeLists.txt).
  if(NOT "$ENV{CI}" STREQUAL "")
    message(FATAL_ERROR "colcon not found under CI: install colcon, python3-colcon-cmake "
      "and python3-colcon-ros (scripts/packages)")
  endif()
  message(STATUS "colcon_workspace skipped: colcon not found")
  return()
endif()

file(REMOVE_RECURSE "${WORK_DIR}")
file(MAKE_DIRECTORY "${WORK_DIR}/src")
# Symbolic links, as a developer clones into src/: colcon follows them and stops
# descending at a package, so the consumer inside this tree is found only once.
file(CREATE_LINK "${SOURCE_DIR}" "${WORK_DIR}/src/pcl_spherical_meshless" SYMBOLIC)
file(CREATE_LINK "${SOURCE_DIR}/test/colcon/meshless_colcon_consumer"
  "${WORK_DIR}/src/meshless_colcon_consumer" SYMBOLIC)

function(run_step)
  execute_process(COMMAND ${ARGN} WORKING_DIRECTORY "${WORK_DIR}"
    RESULT_VARIABLE result OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT result EQUAL 0)
    message(FATAL_ERROR "step failed (${result}): ${ARGN}\n${out}\n${err}")
  endif()
  message(STATUS "${out}")
endfunction()

set(cmake_args -DMESHLESS_BUILD_TESTS=OFF -DMESHLESS_BUILD_SAMPLES=OFF
  -DMESHLESS_BUILD_BENCHMARKS=OFF -DCMAKE_BUILD_TYPE=Release)
if(LAUNCHER)
  list(APPEND cmake_args -DCMAKE_CXX_COMPILER_LAUNCHER=${LAUNCHER}
    -DCMAKE_C_COMPILER_LAUNCHER=${LAUNCHER})
endif()
# One package at a time and two compile jobs: the library alone takes minutes, and
# colcon would otherwise start a make job per core for each package.
run_step(${CMAKE_COMMAND} -E env MAKEFLAGS=-j2
  "${COLCON}" --log-base "${WORK_DIR}/log" build
    --base-paths "${WORK_DIR}/src"
    --build-base "${WORK_DIR}/build"
    --install-base "${WORK_DIR}/install"
    --parallel-workers 1
    --event-handlers console_direct- console_cohesion+ desktop_notification- status-
    --cmake-args ${cmake_args})

# The consumer through the workspace's own environment script, as a user runs it.
# Anything on stderr fails too: the setup scripts name hooks they cannot find there
# (a package declaring ament_cmake that ament never registered).
execute_process(COMMAND sh -c ". \"${WORK_DIR}/install/setup.sh\" && meshless_colcon_consumer"
  RESULT_VARIABLE result OUTPUT_VARIABLE out ERROR_VARIABLE err)
message(STATUS "${out}")
if(NOT result EQUAL 0 OR NOT err STREQUAL "")
  message(FATAL_ERROR "the consumer failed in the workspace's environment (${result}):\n${err}")
endif()
