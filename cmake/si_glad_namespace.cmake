# cmake -P script: moves a generated glad 2 GL loader into namespace si::glad, so that si::gl
# defines no global GL symbol and links beside a host's own glad (docs/rendering.md, "A guest in
# the host's engine"). glad 2.0's C output declares every function pointer and flag as
#   GLAD_API_CALL PFNGLBLENDFUNCPROC glad_glBlendFunc;
#   #define glBlendFunc glad_glBlendFunc
# inside extern "C". This script
#   - wraps each GLAD_API_CALL declaration of the header in namespace si::glad,
#   - points each `#define glX glad_glX` at ::si::glad::glad_glX,
#   - gives the header's extern "C" block C++ linkage (so the names are mangled into si::glad),
#   - writes the loader's source as C++ with its definitions inside namespace si::glad,
# and fails when the generated files do not have the shape it expects (a newer glad), rather
# than leaving a global symbol behind. The symbol check (tests/consumer/check_symbols.cmake)
# verifies the result on the built libraries.
# Usage: cmake -DHEADER_IN=... -DSOURCE_IN=... -DHEADER_OUT=... -DSOURCE_OUT=... -P this file
# SPDX-License-Identifier: MIT (see LICENSE)
cmake_minimum_required(VERSION 3.25)
foreach(v HEADER_IN SOURCE_IN HEADER_OUT SOURCE_OUT)
  if(NOT DEFINED ${v})
    message(FATAL_ERROR "si_glad_namespace.cmake: ${v} is not set")
  endif()
endforeach()

set(open_ns "namespace si { namespace glad {")
set(close_ns "} }")

# ---- The header.
file(READ "${HEADER_IN}" header)
string(FIND "${header}" "extern \"C\" {" c_block)
if(c_block EQUAL -1)
  message(FATAL_ERROR "si_glad_namespace: no extern \"C\" block in ${HEADER_IN}")
endif()
string(REPLACE "extern \"C\" {" "extern \"C++\" {" header "${header}")
# Every exported declaration: the function pointers, the version and extension flags, the loader
# functions. Each is one line ending in ';'.
string(REGEX MATCHALL "\nGLAD_API_CALL [^\n]*;" declarations "${header}")
list(LENGTH declarations declaration_count)
if(declaration_count LESS 100)
  message(FATAL_ERROR "si_glad_namespace: only ${declaration_count} GLAD_API_CALL declarations in "
                      "${HEADER_IN}; the generator's output changed")
endif()
string(REGEX REPLACE "\n(GLAD_API_CALL [^\n]*;)" "\n${open_ns} \\1 ${close_ns}" header "${header}")
string(REGEX REPLACE "\n#define (gl[A-Za-z0-9_]+) glad_(gl[A-Za-z0-9_]+)"
       "\n#define \\1 ::si::glad::glad_\\2" header "${header}")
# Nothing may stay outside the namespace (a multi-line declaration would).
string(REGEX MATCHALL "\nGLAD_API_CALL" left_over "${header}")
if(left_over)
  message(FATAL_ERROR "si_glad_namespace: a GLAD_API_CALL declaration of ${HEADER_IN} is not one "
                      "line; the generator's output changed")
endif()
string(PREPEND header "// Generated from glad 2's output by cmake/si_glad_namespace.cmake: every symbol is "
                      "in namespace si::glad.\n")
file(WRITE "${HEADER_OUT}" "${header}")

# ---- The source: its definitions between the extern "C" guards, inside the namespace.
file(READ "${SOURCE_IN}" source)
set(c_open "#ifdef __cplusplus\nextern \"C\" {\n#endif")
set(c_close "#ifdef __cplusplus\n}\n#endif")
string(FIND "${source}" "${c_open}" first_open)
string(FIND "${source}" "${c_close}" last_close REVERSE)
if(first_open EQUAL -1 OR last_close EQUAL -1 OR last_close LESS first_open)
  message(FATAL_ERROR "si_glad_namespace: no extern \"C\" guards in ${SOURCE_IN}")
endif()
string(LENGTH "${c_open}" open_length)
string(LENGTH "${c_close}" close_length)
string(SUBSTRING "${source}" 0 ${first_open} before)
math(EXPR body_start "${first_open} + ${open_length}")
math(EXPR body_length "${last_close} - ${body_start}")
string(SUBSTRING "${source}" ${body_start} ${body_length} body)
math(EXPR after_start "${last_close} + ${close_length}")
string(SUBSTRING "${source}" ${after_start} -1 after)
file(WRITE "${SOURCE_OUT}"
     "// Generated from glad 2's output by cmake/si_glad_namespace.cmake.\n"
     "${before}namespace si {\nnamespace glad {\n${body}}  // namespace glad\n}  // namespace si\n${after}")
