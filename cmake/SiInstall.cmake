# Install rules and the relocatable CMake package `SkinnedInstancing`. Each layer is a component
# with an export set of its own, so find_package(SkinnedInstancing COMPONENTS core crowd gl)
# looks for those layers' dependencies only (no meshoptimizer or tinygltf for a runtime that
# only loads and draws palettes), and no exported target names a path of the build machine
# (si::headless's libraries are imported targets found again by SiHeadlessDeps.cmake).
# SPDX-License-Identifier: MIT (see LICENSE)
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

set(si_package_dir "${CMAKE_INSTALL_LIBDIR}/cmake/SkinnedInstancing")
install(DIRECTORY "${PROJECT_SOURCE_DIR}/include/si" DESTINATION "${CMAKE_INSTALL_INCLUDEDIR}")
get_property(si_installed_targets GLOBAL PROPERTY SI_INSTALLED_TARGETS)
set(SI_PACKAGE_COMPONENTS "")
foreach(target IN LISTS si_installed_targets)
  get_target_property(component ${target} EXPORT_NAME)
  list(APPEND SI_PACKAGE_COMPONENTS ${component})
  install(TARGETS ${target}
          EXPORT SkinnedInstancing_${component}
          ARCHIVE DESTINATION "${CMAKE_INSTALL_LIBDIR}"
          LIBRARY DESTINATION "${CMAKE_INSTALL_LIBDIR}"
          INCLUDES DESTINATION "${CMAKE_INSTALL_INCLUDEDIR}")
  install(EXPORT SkinnedInstancing_${component}
          NAMESPACE si::
          FILE SkinnedInstancing_${component}Targets.cmake
          DESTINATION "${si_package_dir}")
endforeach()

# The public GLSL include (si_skinning.glsl and the files it includes), for engines that build
# their own shaders on it; the package's SkinnedInstancing_GLSL_DIR names the folder.
set(SI_GLSL_INSTALL_DIR "${CMAKE_INSTALL_DATADIR}/SkinnedInstancing/glsl")
get_property(si_glsl_files GLOBAL PROPERTY SI_GLSL_PUBLIC_FILES)
if(si_glsl_files)
  install(FILES ${si_glsl_files} DESTINATION "${SI_GLSL_INSTALL_DIR}")
endif()

configure_package_config_file(
  "${PROJECT_SOURCE_DIR}/cmake/SkinnedInstancingConfig.cmake.in"
  "${PROJECT_BINARY_DIR}/SkinnedInstancingConfig.cmake"
  INSTALL_DESTINATION "${si_package_dir}"
  PATH_VARS SI_GLSL_INSTALL_DIR)
# Minor versions add API; a major version may break it.
write_basic_package_version_file(
  "${PROJECT_BINARY_DIR}/SkinnedInstancingConfigVersion.cmake"
  COMPATIBILITY SameMajorVersion)
install(FILES "${PROJECT_BINARY_DIR}/SkinnedInstancingConfig.cmake"
              "${PROJECT_BINARY_DIR}/SkinnedInstancingConfigVersion.cmake"
              "${PROJECT_SOURCE_DIR}/cmake/SiHeadlessDeps.cmake"
        DESTINATION "${si_package_dir}")
