# Install rules and the relocatable CMake package `SkinnedInstancing`.
# SPDX-License-Identifier: MIT (see LICENSE)
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

install(DIRECTORY "${PROJECT_SOURCE_DIR}/include/si" DESTINATION "${CMAKE_INSTALL_INCLUDEDIR}")
get_property(si_installed_targets GLOBAL PROPERTY SI_INSTALLED_TARGETS)
install(TARGETS ${si_installed_targets}
        EXPORT SkinnedInstancingTargets
        ARCHIVE DESTINATION "${CMAKE_INSTALL_LIBDIR}"
        LIBRARY DESTINATION "${CMAKE_INSTALL_LIBDIR}"
        INCLUDES DESTINATION "${CMAKE_INSTALL_INCLUDEDIR}")
install(EXPORT SkinnedInstancingTargets
        NAMESPACE si::
        DESTINATION "${CMAKE_INSTALL_LIBDIR}/cmake/SkinnedInstancing")

# The public GLSL include (si_skinning.glsl and the files it includes), for engines that build
# their own shaders on it; the package's SkinnedInstancing_GLSL_DIR names the folder.
set(SI_GLSL_INSTALL_DIR "${CMAKE_INSTALL_DATADIR}/SkinnedInstancing/glsl")
get_property(si_glsl_files GLOBAL PROPERTY SI_GLSL_PUBLIC_FILES)
if(si_glsl_files)
  install(FILES ${si_glsl_files} DESTINATION "${SI_GLSL_INSTALL_DIR}")
endif()

set(SI_PACKAGE_WITH_GLTF ${SI_WITH_GLTF})
set(SI_PACKAGE_WITH_GL ${SI_WITH_GL})
configure_package_config_file(
  "${PROJECT_SOURCE_DIR}/cmake/SkinnedInstancingConfig.cmake.in"
  "${PROJECT_BINARY_DIR}/SkinnedInstancingConfig.cmake"
  INSTALL_DESTINATION "${CMAKE_INSTALL_LIBDIR}/cmake/SkinnedInstancing"
  PATH_VARS SI_GLSL_INSTALL_DIR)
# Minor versions add API; a major version may break it.
write_basic_package_version_file(
  "${PROJECT_BINARY_DIR}/SkinnedInstancingConfigVersion.cmake"
  COMPATIBILITY SameMajorVersion)
install(FILES "${PROJECT_BINARY_DIR}/SkinnedInstancingConfig.cmake"
              "${PROJECT_BINARY_DIR}/SkinnedInstancingConfigVersion.cmake"
        DESTINATION "${CMAKE_INSTALL_LIBDIR}/cmake/SkinnedInstancing")
