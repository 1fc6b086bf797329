# Building for the browser with Emscripten (scripts/web.sh, docs/web.md): what the Emscripten
# build needs that the native one finds with find_package.
#   - glm is header-only: its Debian headers are used through a folder that holds only a link to
#     /usr/include/glm (adding /usr/include itself would put glibc's headers before
#     Emscripten's).
#   - Only the runtime layers are built (si::core, si::crowd, si::gl without si::headless): the
#     baker, glTF import and the offscreen contexts need native libraries. The page's palette is
#     baked natively by si-bake and embedded into the page's files.
# SPDX-License-Identifier: MIT (see LICENSE)
find_path(SI_HOST_GLM_INCLUDE glm/glm.hpp PATHS /usr/include NO_CMAKE_FIND_ROOT_PATH
          NO_DEFAULT_PATH REQUIRED DOC "The host's glm headers (Debian package libglm-dev)")
set(si_web_include "${PROJECT_BINARY_DIR}/web_include")
file(MAKE_DIRECTORY "${si_web_include}")
file(CREATE_LINK "${SI_HOST_GLM_INCLUDE}/glm" "${si_web_include}/glm" SYMBOLIC)
add_library(glm::glm INTERFACE IMPORTED)
target_include_directories(glm::glm SYSTEM INTERFACE "${si_web_include}")
foreach(opt SI_BUILD_TESTS SI_BUILD_TOOLS SI_BUILD_BENCHMARKS SI_WITH_GLTF SI_INSTALL
            SI_BUILD_FUZZERS SI_SANITIZE)
  set(${opt} OFF CACHE BOOL "Off in the Emscripten build (cmake/SiWeb.cmake)" FORCE)
endforeach()
