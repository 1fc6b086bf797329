# Generates the glad 2 OpenGL 4.5 core loader at build time with Debian's python3-glad.
# The generated files live in the build tree only (never committed) and are compiled into si_gl;
# no glad header appears in a public si header.
# SPDX-License-Identifier: MIT (see LICENSE)
find_program(SI_GLAD_EXECUTABLE glad HINTS /usr/bin REQUIRED
             DOC "glad 2 loader generator (Debian package python3-glad)")
set(SI_GLAD_DIR "${PROJECT_BINARY_DIR}/generated/glad")
set(SI_GLAD_SOURCES "${SI_GLAD_DIR}/src/gl.c" "${SI_GLAD_DIR}/include/glad/gl.h"
                    "${SI_GLAD_DIR}/include/KHR/khrplatform.h")
add_custom_command(
  OUTPUT ${SI_GLAD_SOURCES}
  COMMAND "${SI_GLAD_EXECUTABLE}" --quiet --reproducible --api gl:core=4.5
          --extensions GL_KHR_debug --out-path "${SI_GLAD_DIR}" c
  COMMENT "Generating the glad GL 4.5 core loader"
  VERBATIM)
