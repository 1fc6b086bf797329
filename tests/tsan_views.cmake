# The tsan.crowd_views test (tests/CMakeLists.txt): the view tests built with ThreadSanitizer in
# a GPU-free tree of their own, then run; any race TSan reports fails them.
# SPDX-License-Identifier: MIT (see LICENSE)
# cmake -DSOURCE=<repo> -DBINARY=<tree> -DGENERATOR=<generator> -DCXX=<c++> -DC=<cc> -P tsan_views.cmake
foreach(step configure build run)
  if(step STREQUAL configure)
    set(command "${CMAKE_COMMAND}" -S "${SOURCE}" -B "${BINARY}" -G "${GENERATOR}"
        -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_COMPILER=${CXX} -DCMAKE_C_COMPILER=${C}
        -DSI_TSAN=ON -DSI_WITH_GL=OFF -DSI_WITH_GLTF=OFF -DSI_BUILD_EXAMPLES=OFF
        -DSI_BUILD_TOOLS=OFF -DSI_BUILD_BENCHMARKS=OFF -DSI_INSTALL=OFF)
  elseif(step STREQUAL build)
    set(command "${CMAKE_COMMAND}" --build "${BINARY}" --target si_crowd_view_tests)
  else()
    set(ENV{TSAN_OPTIONS} "halt_on_error=1:second_deadlock_stack=1")
    set(command "${BINARY}/tests/si_crowd_view_tests")
  endif()
  execute_process(COMMAND ${command} RESULT_VARIABLE result)
  if(NOT result EQUAL 0)
    message(FATAL_ERROR "tsan.crowd_views: the ${step} step failed (${result})")
  endif()
endforeach()
