# Imported targets for si::headless's private libraries, found by name both where the library
# is built and where the installed package is used (SkinnedInstancingConfig.cmake includes this
# file too), so the exported targets name SkinnedInstancing::OSMesa and SkinnedInstancing::stb
# instead of carrying a path of the build machine. Reads SI_HEADLESS (the back-ends built in);
# sets SI_HEADLESS_DEPS_FOUND and, when something is missing, SI_HEADLESS_DEPS_MISSING.
# SPDX-License-Identifier: MIT (see LICENSE)
set(SI_HEADLESS_DEPS_FOUND TRUE)
set(SI_HEADLESS_DEPS_MISSING "")
if("OSMESA" IN_LIST SI_HEADLESS AND NOT TARGET SkinnedInstancing::OSMesa)
  find_library(SI_OSMESA_LIBRARY OSMesa DOC "Mesa's OSMesa (libosmesa6-dev)")
  if(SI_OSMESA_LIBRARY)
    add_library(SkinnedInstancing::OSMesa UNKNOWN IMPORTED)
    set_target_properties(SkinnedInstancing::OSMesa PROPERTIES
                          IMPORTED_LOCATION "${SI_OSMESA_LIBRARY}")
  else()
    set(SI_HEADLESS_DEPS_FOUND FALSE)
    list(APPEND SI_HEADLESS_DEPS_MISSING "OSMesa (libosmesa6-dev)")
  endif()
endif()
if(NOT TARGET SkinnedInstancing::stb)
  # Debian's libstb, static when available so binaries carry it.
  find_library(SI_STB_LIBRARY NAMES libstb.a stb DOC "Debian's libstb (libstb-dev)")
  if(SI_STB_LIBRARY)
    add_library(SkinnedInstancing::stb UNKNOWN IMPORTED)
    set_target_properties(SkinnedInstancing::stb PROPERTIES IMPORTED_LOCATION "${SI_STB_LIBRARY}")
  else()
    set(SI_HEADLESS_DEPS_FOUND FALSE)
    list(APPEND SI_HEADLESS_DEPS_MISSING "stb (libstb-dev)")
  endif()
endif()
