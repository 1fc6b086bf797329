# cmake -P script: builds the library and the consumer project in WORK_DIR, then runs it.
# MODE=find_package: configure + build + install the library (release, no tests/examples), then
#   build the consumer against the install prefix with find_package(SkinnedInstancing).
# MODE=add_subdirectory: build the consumer with the library source added as a subdirectory.
cmake_minimum_required(VERSION 3.25)
foreach(v SOURCE_DIR WORK_DIR MODE GENERATOR)
  if(NOT DEFINED ${v})
    message(FATAL_ERROR "run_consumer.cmake: ${v} is not set")
  endif()
endforeach()

function(run)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "command failed (${rc}): ${ARGN}")
  endif()
endfunction()

file(REMOVE_RECURSE "${WORK_DIR}")
set(consumer_src "${SOURCE_DIR}/tests/consumer/project")
set(common -G "${GENERATOR}" -DCMAKE_BUILD_TYPE=Release)
if(MODE STREQUAL "find_package")
  run("${CMAKE_COMMAND}" -S "${SOURCE_DIR}" -B "${WORK_DIR}/lib-build" ${common}
      -DSI_BUILD_TESTS=OFF -DSI_BUILD_EXAMPLES=OFF -DSI_BUILD_BENCHMARKS=OFF
      "-DCMAKE_INSTALL_PREFIX=${WORK_DIR}/prefix")
  run("${CMAKE_COMMAND}" --build "${WORK_DIR}/lib-build" --parallel 2)
  run("${CMAKE_COMMAND}" --install "${WORK_DIR}/lib-build")
  run("${CMAKE_COMMAND}" -S "${consumer_src}" -B "${WORK_DIR}/consumer-build" ${common}
      "-DCMAKE_PREFIX_PATH=${WORK_DIR}/prefix" -DSI_CONSUMER_MODE=find_package)
elseif(MODE STREQUAL "add_subdirectory")
  run("${CMAKE_COMMAND}" -S "${consumer_src}" -B "${WORK_DIR}/consumer-build" ${common}
      "-DSI_SOURCE_DIR=${SOURCE_DIR}" -DSI_CONSUMER_MODE=add_subdirectory)
else()
  message(FATAL_ERROR "unknown MODE ${MODE}")
endif()
run("${CMAKE_COMMAND}" --build "${WORK_DIR}/consumer-build" --parallel 2)
run("${WORK_DIR}/consumer-build/si_consumer")
