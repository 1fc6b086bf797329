# si_embed_glsl(<output.cpp> SHADER_DIR <dir> FILES <name>...): generates, at build time, a C++
# source holding every named shader file of SHADER_DIR as a string, with its `#include "x"`
# lines replaced by the included file (recursively, from SHADER_DIR), in the table
# si::detail::kEmbeddedShaders (src/gl/programs/embedded_shaders.h). No runtime dependency: the
# shaders are part of the library. Regenerated when a shader file changes.
# SPDX-License-Identifier: MIT (see LICENSE)
set(SI_EMBED_GLSL_SCRIPT "${CMAKE_CURRENT_LIST_DIR}/embed_glsl.cmake")

function(si_embed_glsl output)
  cmake_parse_arguments(ARG "" "SHADER_DIR" "FILES" ${ARGN})
  set(depends "${SI_EMBED_GLSL_SCRIPT}")
  foreach(f ${ARG_FILES})
    list(APPEND depends "${ARG_SHADER_DIR}/${f}")
  endforeach()
  string(REPLACE ";" "|" files "${ARG_FILES}")
  add_custom_command(
    OUTPUT "${output}"
    COMMAND "${CMAKE_COMMAND}" "-DSHADER_DIR=${ARG_SHADER_DIR}" "-DFILES=${files}"
            "-DOUTPUT=${output}" -P "${SI_EMBED_GLSL_SCRIPT}"
    DEPENDS ${depends}
    COMMENT "Embedding the GLSL shaders"
    VERBATIM)
endfunction()
