# Shared compile settings for every SkinnedInstancing target.
# SPDX-License-Identifier: MIT (see LICENSE)

# si_configure_target(<target>): C++17, warnings, optional -Werror and sanitizers.
function(si_configure_target target)
  target_compile_features(${target} PUBLIC cxx_std_17)
  set_target_properties(${target} PROPERTIES CXX_EXTENSIONS OFF POSITION_INDEPENDENT_CODE ON)
  if(MSVC)
    target_compile_options(${target} PRIVATE /W4 $<$<BOOL:${SI_WERROR}>:/WX>)
  else()
    target_compile_options(${target} PRIVATE -Wall -Wextra -Wshadow $<$<BOOL:${SI_WERROR}>:-Werror>)
  endif()
endfunction()

# What must round exactly as the GPU's `precise` shaders (the crowd's culling and records, the
# lane tests): no fused multiply-adds, whatever -march says. GCC and Clang: -ffp-contract=off;
# MSVC: /fp:precise, which contracts only under /fp:contract.
if(MSVC)
  set(SI_NO_FP_CONTRACT /fp:precise)
else()
  set(SI_NO_FP_CONTRACT -ffp-contract=off)
endif()

# The portable lanes (SI_PORTABLE_LANES) for the whole build tree.
if(SI_PORTABLE_LANES)
  add_compile_definitions(SI_PORTABLE_LANES)
endif()

# Sanitizers apply to the whole build tree (libraries, tests, examples) so that
# the instrumented code and its runtime agree.
if(SI_SANITIZE)
  if(MSVC)
    message(FATAL_ERROR "SI_SANITIZE is only supported with GCC and Clang")
  endif()
  add_compile_options(-fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=undefined)
  add_link_options(-fsanitize=address,undefined)
endif()
if(SI_TSAN)
  if(MSVC OR SI_SANITIZE)
    message(FATAL_ERROR "SI_TSAN needs GCC or Clang, and excludes SI_SANITIZE")
  endif()
  add_compile_options(-fsanitize=thread -fno-omit-frame-pointer)
  add_link_options(-fsanitize=thread)
endif()

# si_add_layer(<layer> SOURCES ... [PUBLIC_DEPS ...] [PRIVATE_DEPS ...])
# Adds the static library si_<layer> with the alias si::<layer>, exported as si::<layer>.
function(si_add_layer layer)
  cmake_parse_arguments(ARG "" "" "SOURCES;PUBLIC_DEPS;PRIVATE_DEPS" ${ARGN})
  set(target si_${layer})
  add_library(${target} STATIC ${ARG_SOURCES})
  add_library(si::${layer} ALIAS ${target})
  set_target_properties(${target} PROPERTIES EXPORT_NAME ${layer} OUTPUT_NAME si_${layer})
  target_include_directories(${target} PUBLIC
    $<BUILD_INTERFACE:${PROJECT_SOURCE_DIR}/include>
    $<INSTALL_INTERFACE:include>)
  target_include_directories(${target} PRIVATE ${PROJECT_SOURCE_DIR}/src)
  target_link_libraries(${target} PUBLIC ${ARG_PUBLIC_DEPS} PRIVATE ${ARG_PRIVATE_DEPS})
  si_configure_target(${target})
  set_property(GLOBAL APPEND PROPERTY SI_INSTALLED_TARGETS ${target})
endfunction()
