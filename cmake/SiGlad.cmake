# Generates the glad 2 OpenGL 4.5 core loader at build time with Debian's python3-glad, then
# moves it into namespace si::glad (cmake/si_glad_namespace.cmake), so that si::gl exports no
# global GL symbol and links beside an engine's own glad. The generated files live in the build
# tree only (never committed) and are compiled into si_gl; no glad header appears in a public si
# header.
# SPDX-License-Identifier: MIT (see LICENSE)
find_program(SI_GLAD_EXECUTABLE glad HINTS /usr/bin REQUIRED
             DOC "glad 2 loader generator (Debian package python3-glad)")
set(si_glad_raw "${PROJECT_BINARY_DIR}/generated/glad_c")
set(SI_GLAD_DIR "${PROJECT_BINARY_DIR}/generated/glad")
set(SI_GLAD_SOURCES "${SI_GLAD_DIR}/src/gl.cpp" "${SI_GLAD_DIR}/include/glad/gl.h"
                    "${SI_GLAD_DIR}/include/KHR/khrplatform.h")
add_custom_command(
  OUTPUT ${SI_GLAD_SOURCES}
  COMMAND "${SI_GLAD_EXECUTABLE}" --quiet --reproducible --api gl:core=4.5
          --extensions GL_KHR_debug --out-path "${si_glad_raw}" c
  COMMAND "${CMAKE_COMMAND}" -E make_directory "${SI_GLAD_DIR}/src" "${SI_GLAD_DIR}/include/glad"
          "${SI_GLAD_DIR}/include/KHR"
  COMMAND "${CMAKE_COMMAND}" -E copy "${si_glad_raw}/include/KHR/khrplatform.h"
          "${SI_GLAD_DIR}/include/KHR/khrplatform.h"
  COMMAND "${CMAKE_COMMAND}" -DHEADER_IN=${si_glad_raw}/include/glad/gl.h
          -DSOURCE_IN=${si_glad_raw}/src/gl.c -DHEADER_OUT=${SI_GLAD_DIR}/include/glad/gl.h
          -DSOURCE_OUT=${SI_GLAD_DIR}/src/gl.cpp
          -P "${PROJECT_SOURCE_DIR}/cmake/si_glad_namespace.cmake"
  DEPENDS "${PROJECT_SOURCE_DIR}/cmake/si_glad_namespace.cmake"
  COMMENT "Generating the glad GL 4.5 core loader in namespace si::glad"
  VERBATIM)
