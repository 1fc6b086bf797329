# cmake -P script: the link hygiene check. Lists the global symbols each static library defines
# (nm) and fails on any outside namespace si, so that the library links into a host that has
# its own glad, stb or anything else without a clash and without one definition silently
# standing in for another.
#
# Accepted, by their Itanium-mangled names: names in namespace si and its nested namespaces
# (_ZN2si..., const members _ZNK2si...), their vtables, typeinfo and VTTs, guard variables and
# local statics of si functions, thunks to si members, and AddressSanitizer's __odr_asan.<name>
# twins of accepted names (sanitized builds). The documented exception: weak definitions
# (nm types W, V, w, v and u: inline functions, template instantiations such as
# std::vector<si::X> members, static members of class templates). The linker merges those by
# design (one definition rule); they can never cause a multiple-definition error.
#
# Usage: cmake -DNM=<nm> -DLIBRARIES=<lib.a>,<lib.a>... -P check_symbols.cmake
#        (or -DLIBRARY_DIR=<dir> to check every lib*.a in a folder, e.g. an install prefix)
# SPDX-License-Identifier: MIT (see LICENSE)
cmake_minimum_required(VERSION 3.25)
if(NOT NM)
  message(FATAL_ERROR "check_symbols: NM is not set")
endif()
string(REPLACE "," ";" LIBRARIES "${LIBRARIES}")
if(LIBRARY_DIR)
  file(GLOB dir_libraries "${LIBRARY_DIR}/lib*.a")
  list(APPEND LIBRARIES ${dir_libraries})
endif()
if(NOT LIBRARIES)
  message(FATAL_ERROR "check_symbols: no library to check (LIBRARIES or LIBRARY_DIR)")
endif()
find_program(CXXFILT c++filt)

set(accepted "^(__odr_asan\\.)?_Z(TV|TI|TS|TT|GV|GVZ|Z|Th[n0-9]*_|Tv[n0-9_]*)?N[rVKO]*2si")
set(offenders "")
set(checked 0)
foreach(lib IN LISTS LIBRARIES)
  execute_process(COMMAND "${NM}" -g --defined-only --format=posix "${lib}"
                  OUTPUT_VARIABLE listing RESULT_VARIABLE rc ERROR_VARIABLE errors)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "check_symbols: ${NM} failed on ${lib}: ${errors}")
  endif()
  string(REPLACE ";" "\\;" listing "${listing}")
  string(REPLACE "\n" ";" lines "${listing}")
  get_filename_component(lib_name "${lib}" NAME)
  foreach(line IN LISTS lines)
    # "name type value size"; archive member headers ("member.o:") have no type.
    if(NOT line MATCHES "^([^ ]+) ([A-Za-z]) ")
      continue()
    endif()
    set(name "${CMAKE_MATCH_1}")
    set(type "${CMAKE_MATCH_2}")
    math(EXPR checked "${checked} + 1")
    if(type MATCHES "^[WVwvu]$" OR name MATCHES "${accepted}")
      continue()
    endif()
    set(shown "${name}")
    if(CXXFILT)
      execute_process(COMMAND "${CXXFILT}" "${name}" OUTPUT_VARIABLE shown
                      OUTPUT_STRIP_TRAILING_WHITESPACE)
    endif()
    list(APPEND offenders "  ${lib_name}: ${type} ${shown}")
  endforeach()
endforeach()
list(LENGTH offenders offender_count)
list(LENGTH LIBRARIES library_count)
if(offender_count GREATER 0)
  list(SUBLIST offenders 0 40 first)
  list(JOIN first "\n" shown)
  message(FATAL_ERROR "check_symbols: ${offender_count} global symbols outside namespace si in "
                      "${library_count} libraries (first 40):\n${shown}")
endif()
message(STATUS "check_symbols: ${checked} global symbols of ${library_count} libraries, all in "
               "namespace si or weak")
