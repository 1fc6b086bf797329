# si_glsl_layouts(<output.h> SHADER_DIR <dir> STRUCTS <file.glsl:StructName>...): generates, at
# build time, a header of the std430 offsets and sizes of the named GLSL structs, computed from
# their declarations (cmake/glsl_layouts.cmake), in namespace si::detail::glsl_layout. A C++
# file static_asserts its twins against it, so a GLSL struct and its C++ twin that drift apart
# fail the build (src/gl/shader_layouts.cpp). Regenerated when a named shader file changes.
# SPDX-License-Identifier: MIT (see LICENSE)
set(SI_GLSL_LAYOUTS_SCRIPT "${CMAKE_CURRENT_LIST_DIR}/glsl_layouts.cmake")

function(si_glsl_layouts output)
  cmake_parse_arguments(ARG "" "SHADER_DIR" "STRUCTS" ${ARGN})
  set(depends "${SI_GLSL_LAYOUTS_SCRIPT}")
  foreach(entry ${ARG_STRUCTS})
    string(REGEX REPLACE ":.*" "" file "${entry}")
    list(APPEND depends "${ARG_SHADER_DIR}/${file}")
  endforeach()
  list(REMOVE_DUPLICATES depends)
  string(REPLACE ";" "|" structs "${ARG_STRUCTS}")
  add_custom_command(
    OUTPUT "${output}"
    COMMAND "${CMAKE_COMMAND}" "-DSHADER_DIR=${ARG_SHADER_DIR}" "-DSTRUCTS=${structs}"
            "-DOUTPUT=${output}" -P "${SI_GLSL_LAYOUTS_SCRIPT}"
    DEPENDS ${depends}
    COMMENT "Laying out the GLSL structs the C++ side shares"
    VERBATIM)
endfunction()
