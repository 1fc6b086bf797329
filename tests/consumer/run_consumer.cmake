# cmake -P script: builds the library and the consumer project in WORK_DIR, then runs it.
# MODE=find_package: configure + build + install the library (release, no tests/examples),
#   check the installed libraries' symbols (tests/symbols/check_symbols.cmake) and that the
#   installed package names no path of this machine outside the prefix, then build the consumer
#   against the install prefix with find_package(SkinnedInstancing).
# MODE=add_subdirectory: build the consumer with the library source added as a subdirectory,
#   without a build type (the library must leave the host's empty CMAKE_BUILD_TYPE alone).
# Then si_consumer (the engine-like host) runs, and si_runtime_consumer (si::core, si::crowd and
# si::gl only) draws from the palette file it wrote.
cmake_minimum_required(VERSION 3.25)
foreach(v SOURCE_DIR WORK_DIR MODE GENERATOR NM)
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
if(MODE STREQUAL "find_package")
  set(prefix "${WORK_DIR}/prefix")
  run("${CMAKE_COMMAND}" -S "${SOURCE_DIR}" -B "${WORK_DIR}/lib-build" -G "${GENERATOR}"
      -DCMAKE_BUILD_TYPE=Release -DSI_BUILD_TESTS=OFF -DSI_BUILD_EXAMPLES=OFF
      -DSI_BUILD_BENCHMARKS=OFF "-DCMAKE_INSTALL_PREFIX=${prefix}")
  run("${CMAKE_COMMAND}" --build "${WORK_DIR}/lib-build" --parallel 2)
  run("${CMAKE_COMMAND}" --install "${WORK_DIR}/lib-build")
  # Link hygiene of what was installed (lib/ or the platform's lib64/, lib/<triplet>/).
  file(GLOB_RECURSE package_config "${prefix}/SkinnedInstancingConfig.cmake")
  if(NOT package_config)
    message(FATAL_ERROR "no SkinnedInstancingConfig.cmake installed under ${prefix}")
  endif()
  get_filename_component(package_dir "${package_config}" DIRECTORY)
  get_filename_component(library_dir "${package_dir}/../.." ABSOLUTE)
  run("${CMAKE_COMMAND}" "-DNM=${NM}" "-DLIBRARY_DIR=${library_dir}"
      -P "${SOURCE_DIR}/tests/symbols/check_symbols.cmake")
  # No absolute path of this machine in the exported targets: only the prefix, through
  # ${_IMPORT_PREFIX}.
  file(GLOB targets_files "${package_dir}/*Targets*.cmake")
  if(NOT targets_files)
    message(FATAL_ERROR "no exported targets installed under ${prefix}")
  endif()
  foreach(f IN LISTS targets_files)
    file(STRINGS "${f}" lines REGEX "INTERFACE_LINK_LIBRARIES|IMPORTED_LOCATION|INTERFACE_INCLUDE")
    foreach(line IN LISTS lines)
      string(REPLACE "\${_IMPORT_PREFIX}/" "" line_without_prefix "${line}")
      if(line_without_prefix MATCHES "(\"|;|:)/")
        message(FATAL_ERROR "${f} names a path of the build machine: ${line}")
      endif()
    endforeach()
  endforeach()
  run("${CMAKE_COMMAND}" -S "${consumer_src}" -B "${WORK_DIR}/consumer-build" -G "${GENERATOR}"
      -DCMAKE_BUILD_TYPE=Release "-DCMAKE_PREFIX_PATH=${prefix}" -DSI_CONSUMER_MODE=find_package)
elseif(MODE STREQUAL "add_subdirectory")
  run("${CMAKE_COMMAND}" -S "${consumer_src}" -B "${WORK_DIR}/consumer-build" -G "${GENERATOR}"
      "-DSI_SOURCE_DIR=${SOURCE_DIR}" -DSI_CONSUMER_MODE=add_subdirectory)
else()
  message(FATAL_ERROR "unknown MODE ${MODE}")
endif()
run("${CMAKE_COMMAND}" --build "${WORK_DIR}/consumer-build" --parallel 2)
run("${WORK_DIR}/consumer-build/si_consumer" "${WORK_DIR}")
run("${WORK_DIR}/consumer-build/si_runtime_consumer" "${WORK_DIR}")
